// What a joint or force sees of the bodies it connects.
//
// Coordinates and velocities per body:
//   planar : q = [x, y, theta]                 v = [xdot, ydot, thetadot]            (3, 3)
//   spatial: q = [x, y, z, e0, e1, e2, e3]     v = [xdot, ydot, zdot, wbar_x, wbar_y, wbar_z] (7, 6)
// Positions are of the mass centre in world axes; wbar is the angular velocity
// in body axes. Every Jacobian a plugin returns is taken with respect to the
// velocity vector v (for spatial bodies: virtual displacement dR and the
// body-frame virtual rotation dpi_bar, book Eq. 7.128), never with respect to
// the Euler parameters themselves.
#pragma once

#include <mbd/sdk/rotation.hpp>

#include <string>
#include <vector>

namespace mbd {

enum class Dimension { Planar, Spatial };

inline const char* to_string(Dimension d) { return d == Dimension::Planar ? "planar" : "spatial"; }
constexpr int coordinates_per_body(Dimension d) { return d == Dimension::Planar ? 3 : 7; }
constexpr int velocities_per_body(Dimension d) { return d == Dimension::Planar ? 3 : 6; }

// Pose and velocity of one planar body, with its rotation matrix evaluated once.
struct PlanarBody {
    Vec2 R = Vec2::Zero();
    double theta = 0.0;
    Vec2 Rdot = Vec2::Zero();
    double omega = 0.0;        // thetadot
    Mat2 A = Mat2::Identity();
    Mat2 A_theta = planar_rotation_derivative(0.0);
    bool ground = false;       // ground: fixed, contributes no Jacobian columns

    void set(const Vec2& position, double angle, const Vec2& velocity, double angular_velocity) {
        R = position;
        theta = angle;
        Rdot = velocity;
        omega = angular_velocity;
        A = planar_rotation(angle);
        A_theta = planar_rotation_derivative(angle);
    }
    Vec2 point(const Vec2& u_bar) const { return R + A * u_bar; }
    Vec2 point_velocity(const Vec2& u_bar) const { return Rdot + omega * (A_theta * u_bar); }
};

// Pose and velocity of one spatial body.
struct SpatialBody {
    Vec3 R = Vec3::Zero();
    Vec4 p = Vec4(1, 0, 0, 0);
    Mat3 A = Mat3::Identity();
    Vec3 Rdot = Vec3::Zero();
    Vec3 omega_bar = Vec3::Zero();  // body axes
    bool ground = false;

    void set(const Vec3& position, const Vec4& euler_parameters, const Vec3& velocity,
             const Vec3& angular_velocity_body) {
        R = position;
        p = euler_parameters;
        A = rotation_from_euler_parameters(euler_parameters);
        Rdot = velocity;
        omega_bar = angular_velocity_body;
    }
    Vec3 omega() const { return A * omega_bar; }
    Vec3 point(const Vec3& u_bar) const { return R + A * u_bar; }
    Vec3 point_velocity(const Vec3& u_bar) const { return Rdot + A * omega_bar.cross(u_bar); }
};

// Static description of a body, given to plugins at creation.
struct BodyInfo {
    std::string name;           // "ground" for the ground
    bool ground = false;
    double mass = 0.0;
    Mat3 inertia = Mat3::Zero();  // planar: inertia(2,2) is J about the mass centre
    // initial configuration (t = 0), world axes
    Vec3 position = Vec3::Zero();
    Mat3 orientation = Mat3::Identity();  // planar: rotation about z by the initial angle
    double angle = 0.0;                   // planar initial angle
};

// A joint or force frame fixed on a body ("marker"): origin u_bar and axes
// A_bar in body coordinates. Planar markers use u_bar.head<2>() and angle.
struct Marker {
    Vec3 u_bar = Vec3::Zero();
    Mat3 A_bar = Mat3::Identity();
    double angle = 0.0;  // planar: marker x axis angle in body axes

    Vec2 u_bar2() const { return u_bar.head<2>(); }
    Vec3 axis_x() const { return A_bar.col(0); }
    Vec3 axis_y() const { return A_bar.col(1); }
    Vec3 axis_z() const { return A_bar.col(2); }
};

// The current state of the bodies an element connects, in the element's order.
class BodyStates {
public:
    double t = 0.0;
    std::vector<const PlanarBody*> planar_bodies;
    std::vector<const SpatialBody*> spatial_bodies;

    int size() const {
        return static_cast<int>(planar_bodies.empty() ? spatial_bodies.size() : planar_bodies.size());
    }
    const PlanarBody& planar(int k) const { return *planar_bodies[k]; }
    const SpatialBody& spatial(int k) const { return *spatial_bodies[k]; }
};

}  // namespace mbd
