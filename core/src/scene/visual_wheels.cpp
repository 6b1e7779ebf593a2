// Wheels of rolling contacts and rotors, drawn as discs with a bar across their face
// (core/src/scene/visual_wheels.hpp).
#include "scene/visual_wheels.hpp"

#include <mbd/scene_document.hpp>
#include <mbd/sdk/rotation.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>

namespace mbd {
namespace {

// A positive number under `key` of `node`, else 0 (the joint itself has checked its keys).
double positive_field(const Param* node, const std::string& key) {
    if (!node || !node->is_map()) return 0.0;
    const auto it = node->fields.find(key);
    if (it == node->fields.end() || !it->second.is_scalar()) return 0.0;
    double value = 0.0;
    if (parse_number(it->second.text, value) != NumberText::Valid || !(value > 0)) return 0.0;
    return value;
}

// A world vector under `key` (3 numbers), else `fallback`.
Vec3 vector_field(const Param* node, const std::string& key, const Vec3& fallback) {
    if (!node || !node->is_map()) return fallback;
    const auto it = node->fields.find(key);
    if (it == node->fields.end() || !it->second.is_list() || it->second.items.size() != 3) return fallback;
    Vec3 v;
    for (int k = 0; k < 3; ++k)
        if (parse_number(it->second.items[k].text, v[k]) != NumberText::Valid) return fallback;
    return v;
}

Mat3 initial_orientation(const Body& body) { return rotation_from_euler_parameters(body.euler_parameters); }

}  // namespace

bool is_rolling_contact(const std::string& joint_type) {
    return joint_type == "rolling_disc" || joint_type == "wheel_rail";
}

std::vector<DerivedWheel> rolling_contact_wheels(const Model& model) {
    std::vector<DerivedWheel> wheels;
    for (size_t j = 0; j < model.joints.size(); ++j) {
        const JointInstance& joint = model.joints[j];
        if (!is_rolling_contact(joint.type) || joint.bodies.size() != 2 || joint.markers.size() != 2) continue;
        const int body = joint.bodies[1];
        if (body == kGround) continue;
        const Param* node = scene_element_node(model, "joints", joint.name);
        DerivedWheel w;
        w.joint = static_cast<int>(j);
        w.body = body;
        if (joint.type == "rolling_disc") {  // the marker on the disc: its centre and axis
            w.radius = positive_field(node, "radius");
            w.centre = joint.markers[1].u_bar;
            w.axis = joint.markers[1].axis_z();
        } else {  // wheel_rail: world keys at t = 0, taken into the wheel body's axes
            const Body& b = model.bodies[body];
            const Mat3 A = initial_orientation(b);
            w.radius = node ? positive_field(node->fields.count("wheel") ? &node->fields.at("wheel") : nullptr, "radius")
                            : 0.0;
            w.centre = A.transpose() * (vector_field(node, "wheel_centre", b.position) - b.position);
            const Vec3 rail_y = joint.bodies[0] == kGround ? joint.markers[0].axis_y() : Vec3::UnitY();
            w.axis = A.transpose() * vector_field(node, "axle", rail_y).normalized();
        }
        if (w.radius > 0 && w.axis.norm() > 0) wheels.push_back(w);
    }
    return wheels;
}

bool rotor_of_inertia(const Body& body, DerivedWheel& rotor) {
    if (!(body.mass > 0)) return false;
    Eigen::SelfAdjointEigenSolver<Mat3> eig(body.inertia);
    const Vec3 I = eig.eigenvalues();  // ascending
    if (!(I[0] > 0) || std::abs(I[1] - I[0]) > 1e-6 * I[2] || !(I[2] > I[1] * (1 + 1e-6))) return false;
    rotor.centre = Vec3::Zero();
    rotor.axis = eig.eigenvectors().col(2);
    rotor.radius = std::sqrt(2.0 * I[2] / body.mass);
    const double h2 = 12.0 * (I[0] / body.mass - 0.25 * rotor.radius * rotor.radius);
    rotor.thickness = h2 > 0 ? std::sqrt(h2) : 0.0;
    return true;
}

double wheel_thickness(const DerivedWheel& wheel, double min_thickness) {
    return std::max({wheel.thickness, min_thickness, 0.08 * wheel.radius});
}

void add_marked_wheel(std::vector<VisualShape>& shapes, const DerivedWheel& wheel, double min_thickness,
                      const Vec3& color) {
    const double thickness = wheel_thickness(wheel, min_thickness);
    const Vec3 axis = wheel.axis.normalized();
    Mat3 frame;  // z along the axis
    frame.col(2) = axis;
    frame.col(0) = any_perpendicular(axis).normalized();
    frame.col(1) = axis.cross(frame.col(0));
    VisualShape disc;
    disc.kind = ShapeKind::Cylinder;
    disc.radius = wheel.radius;
    disc.length = thickness;
    disc.position = wheel.centre;
    disc.rotation = frame;
    disc.color = color;
    shapes.push_back(disc);
    // a bar across the face, standing out of it on both sides: its turning is the body's spin
    VisualShape bar;
    bar.kind = ShapeKind::Box;
    bar.size = Vec3(1.9 * wheel.radius, 0.22 * wheel.radius, 1.3 * thickness);
    bar.position = wheel.centre;
    bar.rotation = frame;
    bar.color = Vec3(0.95, 0.95, 0.92) - 0.75 * color;  // dark on a light disc, light on a dark one
    bar.color = bar.color.cwiseMax(0.05);
    shapes.push_back(bar);
}

}  // namespace mbd
