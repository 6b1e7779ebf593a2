// Derived shapes of turning bodies (core/src/scene/visual_scene.cpp): the wheels of rolling
// contacts (rolling_disc, wheel_rail) at their contact radius, and axisymmetric rotors (a
// gyroscope's), each a disc with a bar across its face so that its turning shows.
#pragma once

#include <mbd/model.hpp>
#include <mbd/visual.hpp>

#include <vector>

namespace mbd {

// A disc in its body's frame: centre, unit axis, radius, thickness.
struct DerivedWheel {
    int joint = -1;  // the rolling contact (index into Model::joints), -1 for a rotor
    int body = -1;
    Vec3 centre = Vec3::Zero();
    Vec3 axis = Vec3::UnitZ();
    double radius = 0.0;
    double thickness = 0.0;  // 0: chosen from the radius
};

// True for joints whose points on their bodies move apart from the ground point as the
// mechanism moves (a wheel rolls away from where it touched): their marker rides on the body.
bool is_rolling_contact(const std::string& joint_type);

// The wheel of each rolling contact with a known radius: rolling_disc's `radius` at the
// disc centre about its axis; wheel_rail's `wheel: {radius}` at `wheel_centre` about `axle`
// (the scene's keys, read from Model::document; none when the document is absent).
std::vector<DerivedWheel> rolling_contact_wheels(const Model& model);

// An axisymmetric, disc-like body (two equal principal moments and a larger third one): the
// thin disc of its mass and axial moment (I_a = m r^2 / 2) about the symmetry axis through
// its mass centre, thickened so that I_t = m r^2 / 4 + m h^2 / 12 where the moments allow it.
bool rotor_of_inertia(const Body& body, DerivedWheel& rotor);

// The disc's thickness: its own, else at least `min_thickness` and 8 % of the radius.
double wheel_thickness(const DerivedWheel& wheel, double min_thickness);

// The disc and the bar across its face (a contrasting colour), appended to `shapes`.
void add_marked_wheel(std::vector<VisualShape>& shapes, const DerivedWheel& wheel, double min_thickness,
                      const Vec3& color);

}  // namespace mbd
