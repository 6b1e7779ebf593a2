// Model -> ExportTree (export_tree.hpp): the mapping rules of docs/import.md, "Export".
#include <mbd/import/export_tree.hpp>

#include <mbd/model_system.hpp>
#include <mbd/scene_document.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <set>

namespace mbd::import {

namespace {

// A body's (or the ground's) frame at the start, and its velocity, all in world axes.
struct Frame {
    Vec3 origin = Vec3::Zero();
    Mat3 axes = Mat3::Identity();
    Vec3 velocity = Vec3::Zero(), angular_velocity = Vec3::Zero();
};

Mat3 about_z(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix(); }

// The state a run of the scene starts from: positions assembled, velocities made consistent
// (the same minimum-norm corrections as simulate's).
State start_of(const Model& model) {
    ModelSystem system(model);
    State start = model.initial_state();
    start.t = 0.0;
    system.assemble(start);
    system.consistent_velocities(start);
    return start;
}

// Spatial q: (R, Euler parameters), v: (Rdot, angular velocity in body axes) per body; planar
// q: (x, y, theta), v: their rates.
Frame body_frame(const Model& model, const State& start, int b) {
    Frame f;
    if (b == kGround) return f;
    if (model.dimension == Dimension::Spatial) {
        f.origin = start.q.segment<3>(7 * b);
        f.axes = rotation_from_euler_parameters(start.q.segment<4>(7 * b + 3).normalized());
        f.velocity = start.v.segment<3>(6 * b);
        f.angular_velocity = f.axes * start.v.segment<3>(6 * b + 3);
    } else {
        f.origin = Vec3(start.q[3 * b], start.q[3 * b + 1], 0.0);
        f.axes = about_z(start.q[3 * b + 2]);
        f.velocity = Vec3(start.v[3 * b], start.v[3 * b + 1], 0.0);
        f.angular_velocity = Vec3(0.0, 0.0, start.v[3 * b + 2]);
    }
    return f;
}

// A marker's axes in world axes (planar: turned by its angle about z).
Mat3 marker_axes(const Model& model, const Frame& body, const Marker& marker) {
    return model.dimension == Dimension::Spatial ? Mat3(body.axes * marker.A_bar) : Mat3(body.axes * about_z(marker.angle));
}

Vec3 marker_point(const Model& model, const Frame& body, const Marker& marker) {
    const Vec3 u = model.dimension == Dimension::Spatial ? marker.u_bar : Vec3(marker.u_bar.x(), marker.u_bar.y(), 0.0);
    return body.origin + body.axes * u;
}

// The relative velocity of `child` to `parent` at the child's origin: (linear, angular), world.
std::pair<Vec3, Vec3> relative_velocity(const Frame& parent, const Frame& child) {
    const Vec3 carried = parent.velocity + parent.angular_velocity.cross(child.origin - parent.origin);
    return {child.velocity - carried, child.angular_velocity - parent.angular_velocity};
}

const std::set<std::string> kTreeJoints = {"revolute", "prismatic", "spherical", "fixed"};

// A rotor, the form the MJCF import gives a joint's armature (docs/import.md): a body pinned to
// the ground by a revolute joint, its mass centre on the pin's axis, whose angle a
// coordinate_coupling ties to the coordinate of a revolute or prismatic joint between two other
// bodies, and which no other joint or force element touches. Its kinetic energy is
// 1/2 I_axis (multiplier qdot)^2 and nothing else: MJCF's armature I_axis multiplier^2.
struct Rotor {
    int body = -1, pin = -1, coupling = -1, joint = -1;
    double armature = 0.0;
};

// One side of a coupling (`follower:` or `leader:`): its two bodies, world axis and coordinate.
struct CouplingSide {
    std::set<int> bodies;
    Vec3 axis = Vec3::UnitZ();
    bool angle = true;
};

bool read_side(const Model& model, const JointInstance& coupling, const Param& node, const char* key, CouplingSide& side) {
    const auto it = node.fields.find(key);
    if (it == node.fields.end() || !it->second.is_map()) return false;
    const Param& s = it->second;
    if (const auto b = s.fields.find("bodies"); b != s.fields.end()) {
        if (!b->second.is_list()) return false;
        for (const Param& name : b->second.items) side.bodies.insert(model.body_index(name.text));
    } else if (coupling.bodies.size() >= 2) {
        side.bodies = {coupling.bodies[0], coupling.bodies[1]};
    }
    if (const auto a = s.fields.find("axis"); a != s.fields.end()) side.axis = a->second.as_vector("axis", 3).normalized();
    if (const auto c = s.fields.find("coordinate"); c != s.fields.end()) side.angle = c->second.text != "travel";
    return side.bodies.size() == 2 && !side.bodies.count(-2);
}

bool parallel(const Vec3& a, const Vec3& b) { return std::abs(std::abs(a.normalized().dot(b.normalized())) - 1.0) < 1e-9; }

// The rotors of a spatial model (none planar: the coupling joint is spatial only).
std::vector<Rotor> find_rotors(const Model& model, const State& start) {
    std::vector<Rotor> rotors;
    if (model.dimension != Dimension::Spatial) return rotors;
    auto joints_on = [&](int b) {
        std::vector<int> on;
        for (size_t j = 0; j < model.joints.size(); ++j)
            if (std::count(model.joints[j].bodies.begin(), model.joints[j].bodies.end(), b)) on.push_back(static_cast<int>(j));
        return on;
    };
    for (size_t c = 0; c < model.joints.size(); ++c) {
        const JointInstance& coupling = model.joints[c];
        const Param* node = coupling.type == "coordinate_coupling" ? scene_element_node(model, "joints", coupling.name) : nullptr;
        CouplingSide follower, leader;
        if (!node || !read_side(model, coupling, *node, "follower", follower) ||
            !read_side(model, coupling, *node, "leader", leader) || !follower.angle || !follower.bodies.count(kGround))
            continue;
        Rotor rotor;
        rotor.coupling = static_cast<int>(c);
        rotor.body = *follower.bodies.rbegin();
        const std::vector<int> on = joints_on(rotor.body);
        if (on.size() != 2 || leader.bodies.count(rotor.body)) continue;
        rotor.pin = on[0] == rotor.coupling ? on[1] : on[0];
        const JointInstance& pin = model.joints[rotor.pin];
        if (pin.type != "revolute" || std::set<int>(pin.bodies.begin(), pin.bodies.end()) != follower.bodies) continue;
        const int ground_end = pin.bodies[0] == kGround ? 0 : 1;
        const Vec3 axis = pin.markers[ground_end].A_bar.col(2), point = pin.markers[ground_end].u_bar;
        const Frame f = body_frame(model, start, rotor.body);
        if (!parallel(axis, follower.axis) || (f.origin - point).cross(axis).norm() > 1e-12 * (1.0 + point.norm())) continue;
        bool loaded = false;
        for (const ForceInstance& force : model.forces)
            loaded |= force.type != "gravity" && std::count(force.bodies.begin(), force.bodies.end(), rotor.body);
        if (loaded) continue;
        for (size_t j = 0; j < model.joints.size(); ++j) {
            const JointInstance& joint = model.joints[j];
            if (joint.type != (leader.angle ? "revolute" : "prismatic") ||
                std::set<int>(joint.bodies.begin(), joint.bodies.end()) != leader.bodies)
                continue;
            const Frame fi = body_frame(model, start, joint.bodies[0]);
            if (parallel(marker_axes(model, fi, joint.markers[0]).col(2), leader.axis)) rotor.joint = static_cast<int>(j);
        }
        if (rotor.joint < 0) continue;
        const double multiplier = node->fields.count("multiplier") ? node->fields.at("multiplier").as_number("multiplier") : 1.0;
        const Vec3 a = axis.normalized();
        rotor.armature = a.dot(f.axes * model.bodies[rotor.body].inertia * f.axes.transpose() * a) * multiplier * multiplier;
        rotors.push_back(rotor);
    }
    return rotors;
}

class TreeBuilder {
public:
    explicit TreeBuilder(const Model& model) : model_(model), start_(start_of(model)) {
        tree_.name = model.name;
        tree_.source = model.source;
        tree_.planar = model.dimension == Dimension::Planar;
        tree_.gravity = model.gravity;
        if (tree_.planar) tree_.gravity.z() = 0.0;
        for (int b = 0; b < model.body_count(); ++b) frames_.push_back(body_frame(model, start_, b));
        adjacent_.resize(model.body_count() + 1);
        for (const Rotor& r : find_rotors(model, start_)) {
            rotor_bodies_.insert(r.body);
            rotor_joints_.insert({r.pin, r.coupling});
            armature_of_[r.joint] = r;
        }
        for (size_t j = 0; j < model.joints.size(); ++j) {
            const JointInstance& joint = model.joints[j];
            if (rotor_joints_.count(static_cast<int>(j))) continue;  // written as its joint's armature
            if (!kTreeJoints.count(joint.type) || joint.bodies.size() != 2) {
                left("joints of a type MJCF and URDF do not have", joint.name + " (" + joint.type + ")",
                     "only revolute, prismatic, spherical and fixed joints and free bodies are written");
                continue;
            }
            for (int k = 0; k < 2; ++k) adjacent_[joint.bodies[k] + 1].push_back(static_cast<int>(j));
        }
    }

    ExportTree build() {
        grow(kGround);
        for (int b = 0; b < model_.body_count(); ++b) {
            if (export_of_.count(b) || rotor_bodies_.count(b)) continue;
            add_free_root(b);
            grow(b);
        }
        add_springs();
        list_the_rest();
        return tree_;
    }

private:
    void left(const std::string& kind, const std::string& name, const std::string& note) {
        for (Unmapped& u : tree_.left_out)
            if (u.kind == kind) {
                u.names.push_back(name);
                return;
            }
        tree_.left_out.push_back({kind, {name}, note});
    }

    ExportBody body_of(int b, int parent) {
        const Body& body = model_.bodies[b];
        ExportBody out;
        out.name = body.name;
        out.parent = parent;
        out.mass = body.mass;
        out.inertia = body.inertia;
        if (tree_.planar) {  // out-of-plane moments that any rigid body may have; the motion stays planar
            const double J = body.inertia(2, 2);
            out.inertia = Vec3(J / 2, J / 2, J).asDiagonal();
        }
        out.position = frames_[b].origin;
        out.rotation = frames_[b].axes;
        return out;
    }

    void add_body(int b, ExportBody body) {
        export_of_[b] = static_cast<int>(tree_.bodies.size());
        tree_.bodies.push_back(std::move(body));
    }

    // A body no joint path leads to from the ground: a free joint (planar: slides along x and y
    // and a hinge about z through its mass centre, MuJoCo's planar idiom).
    void add_free_root(int b) {
        ExportBody body = body_of(b, -1);
        const Frame& f = frames_[b];
        if (!tree_.planar) {
            ExportJoint free{body.name + "_free", ExportJointKind::Free, f.origin};
            const Vec3 w = f.axes.transpose() * f.angular_velocity;
            free.velocity = {f.velocity.x(), f.velocity.y(), f.velocity.z(), w.x(), w.y(), w.z()};
            body.joints.push_back(free);
        } else {
            body.joints.push_back({body.name + "_x", ExportJointKind::Slide, f.origin, Vec3::UnitX(), {f.velocity.x()}});
            body.joints.push_back({body.name + "_y", ExportJointKind::Slide, f.origin, Vec3::UnitY(), {f.velocity.y()}});
            body.joints.push_back({body.name + "_angle", ExportJointKind::Hinge, f.origin, Vec3::UnitZ(), {f.angular_velocity.z()}});
        }
        add_body(b, std::move(body));
    }

    // Breadth first from `root` over the tree joints: each body reached for the first time
    // becomes the child of the joint that reached it; a joint between two bodies reached before
    // closes a loop.
    void grow(int root) {
        std::deque<int> queue{root};
        while (!queue.empty()) {
            const int b = queue.front();
            queue.pop_front();
            for (int j : adjacent_[b + 1]) {
                if (!used_.insert(j).second) continue;
                const JointInstance& joint = model_.joints[j];
                const int other = joint.bodies[0] == b ? joint.bodies[1] : joint.bodies[0];
                if (other == kGround || export_of_.count(other)) {
                    left("joints that close a loop", joint.name, "MJCF and URDF describe trees");
                    continue;
                }
                add_child(b, other, j);
                queue.push_back(other);
            }
        }
    }

    void add_child(int parent, int child, int j) {
        const JointInstance& joint = model_.joints[j];
        ExportBody body = body_of(child, parent == kGround ? -1 : export_of_.at(parent));
        const Frame& p = parent == kGround ? ground_ : frames_[parent];
        const Frame& c = frames_[child];
        const int i = joint.bodies[0] == kGround ? -1 : joint.bodies[0];
        const Frame& fi = i < 0 ? ground_ : frames_[i];
        const Vec3 point = marker_point(model_, fi, joint.markers[0]);
        const Mat3 axes = marker_axes(model_, fi, joint.markers[0]);
        const auto [v, w] = relative_velocity(p, c);
        if (joint.type == "fixed") {
            body.welded_by = joint.name;
        } else if (joint.type == "spherical") {
            const Vec3 rate = c.axes.transpose() * w;
            body.joints.push_back({joint.name, ExportJointKind::Ball, point, Vec3::UnitZ(), {rate.x(), rate.y(), rate.z()}});
        } else if (joint.type == "revolute") {
            const Vec3 axis = tree_.planar ? Vec3::UnitZ() : Vec3(axes.col(2));
            body.joints.push_back({joint.name, ExportJointKind::Hinge, point, axis, {axis.dot(w)}});
        } else {  // prismatic: along marker i's z (spatial) or x (planar)
            const Vec3 axis = tree_.planar ? Vec3(axes.col(0)) : Vec3(axes.col(2));
            body.joints.push_back({joint.name, ExportJointKind::Slide, point, axis, {axis.dot(v)}});
        }
        if (const auto rotor = armature_of_.find(j); rotor != armature_of_.end() && !body.joints.empty()) {
            body.joints.back().armature = rotor->second.armature;
            body.joints.back().rotor = model_.bodies[rotor->second.body].name;
        }
        add_body(child, std::move(body));
        hinge_bodies_[j] = {parent, child};
    }

    // A rotational_spring_damper across a hinge of the tree (same two bodies, its axis along the
    // hinge's) as the hinge's stiffness, springref and damping: MuJoCo's passive torque
    // -k (q - springref) - b qdot is the element's (docs/import.md).
    bool add_spring(const ForceInstance& force) {
        if (force.type != "rotational_spring_damper" || force.bodies.size() != 2) return false;
        const Param* node = scene_element_node(model_, "forces", force.name);
        if (!node || node->fields.count("torque")) return false;
        for (const auto& [j, pair] : hinge_bodies_) {
            const std::set<int> ends{pair.first, pair.second};
            if (ends != std::set<int>{force.bodies[0], force.bodies[1]} || model_.joints[j].type != "revolute") continue;
            ExportJoint& hinge = tree_.bodies[export_of_.at(pair.second)].joints.front();
            const Frame& fi = force.bodies[0] == kGround ? ground_ : frames_[force.bodies[0]];
            const Frame& fj = force.bodies[1] == kGround ? ground_ : frames_[force.bodies[1]];
            const Mat3 ai = marker_axes(model_, fi, force.markers[0]), aj = marker_axes(model_, fj, force.markers[1]);
            if (std::abs(std::abs(ai.col(2).dot(hinge.axis)) - 1.0) > 1e-9) continue;
            const double phi0 = std::atan2(ai.col(1).dot(aj.col(0)), ai.col(0).dot(aj.col(0)));
            const double rest = node->fields.count("rest_angle") ? node->fields.at("rest_angle").as_number("rest_angle") : phi0;
            // the hinge's coordinate grows with the element's angle (s = 1) or against it
            const double s = (pair.second == force.bodies[1] ? 1.0 : -1.0) * (ai.col(2).dot(hinge.axis) > 0 ? 1.0 : -1.0);
            hinge.stiffness = node->fields.count("stiffness") ? node->fields.at("stiffness").as_number("stiffness") : 0.0;
            hinge.damping = node->fields.count("damping") ? node->fields.at("damping").as_number("damping") : 0.0;
            hinge.spring_reference = s * (rest - phi0);
            hinge.spring_name = force.name;
            return true;
        }
        return false;
    }

    // A joint_stop across a hinge or slide of the tree (the same two bodies, its axis along the
    // joint's, its coordinate the joint's) as the joint's limits in the joint's coordinate, zero
    // at the start: a spatial stop's angle is zero there too, a planar one is θ_j − θ_i, its travel
    // is measured from its point on body i to body j's mass centre (docs/scene-format.md), and
    // either may run against the joint.
    bool add_stop(const ForceInstance& force) {
        if (force.type != "joint_stop" || force.bodies.size() != 2) return false;
        const Param* node = scene_element_node(model_, "forces", force.name);
        if (!node) return false;
        const auto& f = node->fields;
        const bool travel = f.count("coordinate") && f.at("coordinate").text == "travel";
        for (const auto& [j, pair] : hinge_bodies_) {
            const std::set<int> ends{pair.first, pair.second};
            if (ends != std::set<int>{force.bodies[0], force.bodies[1]} || model_.joints[j].type != (travel ? "prismatic" : "revolute"))
                continue;
            ExportJoint& joint = tree_.bodies[export_of_.at(pair.second)].joints.front();
            const Frame& fi = force.bodies[0] == kGround ? ground_ : frames_[force.bodies[0]];
            const Frame& fj = force.bodies[1] == kGround ? ground_ : frames_[force.bodies[1]];
            const Mat3 ai = marker_axes(model_, fi, force.markers[0]);
            const Vec3 axis = tree_.planar ? (travel ? Vec3(ai.col(0)) : Vec3::UnitZ()) : Vec3(ai.col(2));
            if (!parallel(axis, joint.axis)) continue;
            const double s = (pair.second == force.bodies[1] ? 1.0 : -1.0) * (axis.dot(joint.axis) > 0 ? 1.0 : -1.0);
            // the coordinate at the start: a spatial angle is zero there, a planar one is θ_j − θ_i
            auto theta = [&](int b) { return b == kGround ? 0.0 : start_.q[3 * b + 2]; };
            const double start = travel       ? axis.dot(fj.origin - marker_point(model_, fi, force.markers[0]))
                                 : tree_.planar ? theta(force.bodies[1]) - theta(force.bodies[0])
                                                : 0.0;
            bool has[2] = {f.count("lower") > 0, f.count("upper") > 0};
            double limit[2] = {has[0] ? f.at("lower").as_number("lower") : 0.0, has[1] ? f.at("upper").as_number("upper") : 0.0};
            for (double& l : limit) l = (l - start) / s;
            if (s < 0) std::swap(has[0], has[1]), std::swap(limit[0], limit[1]);
            joint.has_lower = has[0], joint.lower = limit[0];
            joint.has_upper = has[1], joint.upper = limit[1];
            joint.stop_name = force.name;
            if (!imports_as_written(f))
                left("joint stop laws", force.name,
                     "its limits are written; MJCF and URDF limits carry no restitution or contact law (an import "
                     "gives restitution 0 and a linear law of stiffness 1e8)");
            return true;
        }
        return false;
    }

    // The stop an import makes of a limit (docs/import.md, "Joint limits").
    static bool imports_as_written(const std::map<std::string, Param>& f) {
        auto number = [&](const char* key, double otherwise) { return f.count(key) ? f.at(key).as_number(key) : otherwise; };
        return f.count("law") && f.at("law").text == "hunt_crossley" && number("restitution", -1.0) == 0.0 &&
               number("exponent", 1.5) == 1.0 && number("stiffness", 0.0) == 1e8 && number("damping", 0.0) == 0.0;
    }

    void add_springs() {
        for (const ForceInstance& force : model_.forces) {
            if (force.type == "gravity") continue;  // the model's gravity
            if (!add_spring(force) && !add_stop(force))
                left("force elements", force.name + " (" + force.type + ")",
                     "only gravity, a rotational_spring_damper across a revolute joint, without torque, and a "
                     "joint_stop on a revolute or prismatic joint are written");
        }
    }

    void list_the_rest() {
        for (const Driver& d : model_.drivers) left("drivers", d.name, "MJCF and URDF prescribe no motion");
        for (const Actuator& a : model_.actuators) left("actuators", a.name, "");
        for (const Body& b : model_.bodies)
            if (!b.visuals.empty()) left("visual shapes", b.name, "geometry is not written");
    }

    const Model& model_;
    State start_;
    ExportTree tree_;
    Frame ground_;
    std::vector<Frame> frames_;
    std::vector<std::vector<int>> adjacent_;  // per body + 1 (0: the ground): its tree joints
    std::set<int> used_;
    std::map<int, int> export_of_;                   // model body -> ExportTree body
    std::map<int, std::pair<int, int>> hinge_bodies_;  // tree joint -> (parent, child) model bodies
    std::set<int> rotor_bodies_, rotor_joints_;        // rotors and their pins and couplings
    std::map<int, Rotor> armature_of_;                 // tree joint -> the rotor giving its armature
};

}  // namespace

ExportTree build_export_tree(const Model& model) { return TreeBuilder(model).build(); }

}  // namespace mbd::import
