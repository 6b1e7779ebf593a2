// ImportedScene -> YAML text (scene_writer.hpp).
#include <mbd/import/scene_writer.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <sstream>

#include <Eigen/Geometry>

namespace mbd::import {

namespace {

std::string number(double x) {
    if (x == 0.0) return "0";  // also -0
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", x);
    return text;
}

std::string vector(const Vec3& v) { return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]"; }

std::string matrix(const Mat3& m) {
    const Mat3 s = 0.5 * (m + m.transpose());
    return "[" + vector(s.row(0).transpose()) + ", " + vector(s.row(1).transpose()) + ", " + vector(s.row(2).transpose()) + "]";
}

// The model's name as a plain YAML scalar: letters, digits, '_' and '-' kept, the rest '_'.
std::string label(const std::string& name) {
    std::string out;
    for (char c : name) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
    return out.empty() ? std::string("imported") : out;
}

std::string body_name(const ImportedScene& scene, int index) {
    return index < 0 ? std::string("ground") : scene.bodies[index].name;
}

std::string source(const std::string& where, const std::string& what) {
    return "  # " + (where.empty() ? std::string() : where + ": ") + what + "\n";
}

// A rotation as the scene's {axis, angle}.
std::string rotation_text(const Mat3& r) {
    const Eigen::AngleAxisd turn(r);
    return "{axis: " + vector(turn.axis()) + ", angle: " + number(turn.angle()) + "}";
}

// The body's shapes (posed in world at t = 0) in its frame: origin the mass centre, body axes.
void write_visuals(std::ostringstream& out, const SceneBody& b) {
    if (b.visuals.empty()) return;
    out << "    visual:\n";
    for (const VisualShape& v : b.visuals) {
        out << "      # " << v.where << "\n      - {shape: " << shape_kind_name(v.kind);
        if (v.kind == ShapeKind::Box) out << ", size: " << vector(v.size);
        if (v.kind != ShapeKind::Box && v.kind != ShapeKind::Mesh) out << ", radius: " << number(v.radius);
        if (v.kind == ShapeKind::Cylinder || v.kind == ShapeKind::Capsule) out << ", length: " << number(v.length);
        if (v.kind == ShapeKind::Mesh) out << ", file: \"" << v.mesh_file << "\", scale: " << vector(v.scale);
        out << ", position: " << vector(b.rotation.transpose() * (v.position - b.position))
            << ", rotation: " << rotation_text(b.rotation.transpose() * v.rotation) << ", color: " << vector(v.color) << "}\n";
    }
}

void write_bodies(std::ostringstream& out, const ImportedScene& scene) {
    out << "bodies:\n";
    for (const SceneBody& b : scene.bodies) {
        out << source(b.where, b.comment);
        const Vec4 p = euler_parameters_from_rotation(b.rotation);
        out << "  - name: " << b.name << "\n"
            << "    mass: " << number(b.mass) << "\n"
            << "    inertia: " << matrix(b.inertia) << "\n"
            << "    position: " << vector(b.position) << "\n"
            << "    orientation: {euler_parameters: [" << number(p[0]) << ", " << number(p[1]) << ", " << number(p[2])
            << ", " << number(p[3]) << "]}\n";
        if (!b.velocity.isZero(0.0)) out << "    velocity: " << vector(b.velocity) << "\n";
        if (!b.angular_velocity.isZero(0.0)) out << "    angular_velocity: " << vector(b.angular_velocity) << "\n";
        write_visuals(out, b);
    }
}

// A coordinate_coupling over the bodies of its two joints (each once, in order).
void write_coupling(std::ostringstream& out, const ImportedScene& scene, const SceneCoupling& c) {
    const SceneJoint& f = scene.joints[c.follower];
    const SceneJoint& l = scene.joints[c.leader];
    std::vector<int> bodies;
    for (int b : {f.parent, f.child, l.parent, l.child})
        if (std::find(bodies.begin(), bodies.end(), b) == bodies.end()) bodies.push_back(b);
    auto side = [&](const SceneJoint& j, double start) {
        return "{bodies: [" + body_name(scene, j.parent) + ", " + body_name(scene, j.child) + "], point: " + vector(j.point) +
               ", axis: " + vector(j.axis) + ", coordinate: " + (j.type == "prismatic" ? "travel" : "angle") +
               ", start: " + number(start) + "}";
    };
    out << source(c.where, c.comment);
    out << "  - {name: " << c.name << ", type: coordinate_coupling, bodies: [";
    for (size_t k = 0; k < bodies.size(); ++k) out << (k ? ", " : "") << body_name(scene, bodies[k]);
    out << "], multiplier: " << number(c.multiplier) << ", offset: " << number(c.offset) << ",\n     follower: "
        << side(f, c.follower_start) << ",\n     leader: " << side(l, c.leader_start) << "}\n";
}

void write_joints(std::ostringstream& out, const ImportedScene& scene) {
    if (scene.joints.empty()) return;
    out << "joints:\n";
    for (const SceneJoint& j : scene.joints) {
        out << source(j.where, j.comment.empty() ? scene.format + " joint '" + j.name + "'" : j.comment);
        out << "  - {name: " << j.name << ", type: " << j.type << ", bodies: [" << body_name(scene, j.parent) << ", "
            << body_name(scene, j.child) << "], point: " << vector(j.point);
        if (j.type == "universal")
            out << ", axes: [" << vector(j.axis) << ", " << vector(j.axis2) << "]";
        else if (j.type != "spherical" && j.type != "fixed")
            out << ", axis: " << vector(j.axis);
        if (j.type == "screw") out << ", pitch: " << number(j.pitch);
        out << "}\n";
    }
    for (const SceneCoupling& c : scene.couplings) write_coupling(out, scene, c);
}

void write_stops(std::ostringstream& out, const ImportedScene& scene) {
    for (const SceneStop& s : scene.stops) {
        out << source(s.where, "limits of " + scene.format + " joint '" + s.name.substr(0, s.name.rfind("_limits")) + "'");
        out << "  - {name: " << s.name << ", type: joint_stop, bodies: [" << body_name(scene, s.parent) << ", "
            << body_name(scene, s.child) << "], point: " << vector(s.point) << ", axis: " << vector(s.axis)
            << ", coordinate: " << (s.travel ? "travel" : "angle");
        if (s.has_lower) out << ", lower: " << number(s.lower);
        if (s.has_upper) out << ", upper: " << number(s.upper);
        out << ", restitution: 0, law: hunt_crossley, exponent: 1, stiffness: "
            << number(s.stiffness) << "}\n";
    }
}

void write_forces(std::ostringstream& out, const ImportedScene& scene) {
    if (scene.forces.empty() && scene.stops.empty()) return;
    out << "forces:\n";
    write_stops(out, scene);
    for (const SceneForce& f : scene.forces) {
        out << source(f.where, "stiffness and damping of " + scene.format + " joint '" + f.name + "'");
        out << "  - {name: " << f.name << ", type: rotational_spring_damper, bodies: [" << body_name(scene, f.parent)
            << ", " << body_name(scene, f.child) << "], point: " << vector(f.point) << ", axis: " << vector(f.axis)
            << ", stiffness: " << number(f.stiffness) << ", damping: " << number(f.damping)
            << ", rest_angle: " << number(f.rest_angle) << "}\n";
    }
}

}  // namespace

std::string scene_yaml(const ImportedScene& scene) {
    std::ostringstream out;
    out << "# Imported by `mbd import` from " << scene.file << " (" << scene.format << "; docs/import.md).\n";
    for (const std::string& note : scene.notes) out << "# " << note << "\n";
    const std::string missing = unmapped_summary(scene.unmapped);
    if (!missing.empty()) out << "# Not imported: " << missing << "\n";
    out << "name: " << label(scene.name) << "\n"
        << "dimension: spatial\n"
        << "gravity: " << vector(scene.gravity) << "\n";
    write_bodies(out, scene);
    write_joints(out, scene);
    write_forces(out, scene);
    return out.str();
}

}  // namespace mbd::import
