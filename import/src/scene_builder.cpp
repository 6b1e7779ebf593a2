// SourceTree -> ImportedScene (imported_scene.hpp): the format-independent mapping rules of
// docs/import.md.
#include <mbd/import/imported_scene.hpp>

#include <mbd/sdk/params.hpp>  // InputError
#include <mbd/sdk/text.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <deque>
#include <map>
#include <set>

namespace mbd::import {

namespace {

// mbd names hold letters, digits, '_' and '-' (docs/scene-format.md); `ground` is reserved.
class Names {
public:
    std::string unique(const std::string& wanted, const std::string& fallback) {
        std::string name;
        for (char c : wanted.empty() ? fallback : wanted)
            name += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
        if (name == "ground") name = "ground_";
        std::string candidate = name;
        for (int k = 2; !taken_.insert(candidate).second; ++k) candidate = name + "_" + std::to_string(k);
        return candidate;
    }

private:
    std::set<std::string> taken_;
};

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (size_t k = 0; k < names.size(); ++k) out += (k ? ", " : "") + names[k];
    return out;
}

std::string element(const SourceTree& tree, const SourceBody& body) {
    return tree.format + (tree.format == "URDF" ? " link '" : " body '") + body.name + "'";
}

// A rigid body's mass properties (Shabana Eq. 7.95: each principal moment is at most the sum of
// the other two), within the scene loader's tolerance.
void check_mass_properties(const SourceTree& tree, const SourceBody& body) {
    const std::string what = element(tree, body);
    if (!std::isfinite(body.mass) || body.mass < 0.0)
        throw InputError(body.where, what + ": mass " + format_number(body.mass) +
                                         " is not a mass (give a finite number >= 0, in kg)");
    if (!body.inertia.allFinite())
        throw InputError(body.where, what + ": the inertia has a value that is not a finite number");
    const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Mat3>(body.inertia).eigenvalues();
    const double scale = std::max(moments.cwiseAbs().sum(), 1e-300);
    for (int a = 0; a < 3; ++a) {
        const double others = moments.sum() - moments[a];
        if (moments[a] < -1e-9 * scale || moments[a] > others + 1e-9 * scale)
            throw InputError(body.where,
                             what + ": the inertia is not a rigid body's: its principal moments are " +
                                 format_number(moments[0], 9) + ", " + format_number(moments[1], 9) + ", " +
                                 format_number(moments[2], 9) + ", and " +
                                 (moments[a] < 0 ? format_number(moments[a], 9) + " is negative"
                                                 : format_number(moments[a], 9) + " exceeds the sum of the other two") +
                                 " (every principal moment must lie between 0 and the sum of the other two; "
                                 "check the ixx..izz values and their signs)");
    }
}

// `into` and `part` as one rigid body, in `into`'s body axes.
void merge(SceneBody& into, const SourceBody& part) {
    const double m = into.mass + part.mass;
    if (m <= 0.0) return;
    const Vec3 c = (into.mass * into.position + part.mass * part.com) / m;
    auto about = [&](double mass, const Vec3& at, const Mat3& world_inertia) {
        const Vec3 d = at - c;
        return Mat3(world_inertia + mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
    };
    const Mat3 world = about(into.mass, into.position, into.rotation * into.inertia * into.rotation.transpose()) +
                       about(part.mass, part.com, part.rotation * part.inertia * part.rotation.transpose());
    into.inertia = into.rotation.transpose() * world * into.rotation;
    into.inertia = 0.5 * (into.inertia + into.inertia.transpose());
    into.mass = m;
    into.position = c;
    into.visuals.insert(into.visuals.end(), part.visuals.begin(), part.visuals.end());
}

std::string joint_type(SourceJointKind kind) {
    switch (kind) {
        case SourceJointKind::Hinge: return "revolute";
        case SourceJointKind::Slide: return "prismatic";
        case SourceJointKind::Ball: return "spherical";
        case SourceJointKind::Planar: return "planar";
        case SourceJointKind::Universal: return "universal";
        case SourceJointKind::Screw: return "screw";
        case SourceJointKind::Free: break;
    }
    return "free";
}

// Velocities at t = 0 from the parent's and the joint's (all in world axes).
void propagate_velocities(ImportedScene& scene, const std::vector<const SourceJoint*>& joint_source,
                          const std::vector<int>& parent_joint) {
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
        const int j = parent_joint[b];
        if (j < 0) continue;  // a free body keeps its own
        const SceneJoint& joint = scene.joints[j];
        const SourceJoint& source = *joint_source[j];
        SceneBody& body = scene.bodies[b];
        Vec3 w = Vec3::Zero(), v = Vec3::Zero();
        if (joint.parent >= 0) {
            const SceneBody& parent = scene.bodies[joint.parent];
            w = parent.angular_velocity;
            v = parent.velocity + w.cross(body.position - parent.position);
        }
        Vec3 w_rel = Vec3::Zero();
        if (source.kind == SourceJointKind::Hinge) w_rel = source.rate * joint.axis;
        if (source.kind == SourceJointKind::Ball || source.kind == SourceJointKind::Universal) w_rel = source.angular;
        if (source.kind == SourceJointKind::Slide) v += source.rate * joint.axis;
        if (source.kind == SourceJointKind::Screw) {  // a turn advances pitch / (2 pi) along the axis
            w_rel = source.rate * joint.axis;
            v += source.pitch / (2.0 * M_PI) * source.rate * joint.axis;
        }
        body.angular_velocity = w + w_rel;
        body.velocity = v + w_rel.cross(body.position - joint.point);
    }
}

// The scene as it is built, one source body after another (parents first).
class SceneBuilder {
public:
    explicit SceneBuilder(const SourceTree& tree) : tree_(tree) {
        scene_.name = tree.name;
        scene_.file = tree.file;
        scene_.format = tree.format;
        scene_.gravity = tree.gravity;
        scene_.unmapped = tree.unmapped;
        double total_mass = 0.0;
        for (const SourceBody& body : tree.bodies) {
            check_mass_properties(tree, body);
            total_mass += body.mass;
        }
        frame_mass_ = kFrameMassFraction * std::max(total_mass, 1e-300);
    }

    ImportedScene build() {
        for (size_t i = 0; i < tree_.bodies.size(); ++i) scene_.body_of_source.push_back(add_source_body(i));
        for (size_t b = 0; b < scene_.bodies.size(); ++b) {  // a free body's source velocity is its frame origin's
            if (!free_source_[b]) continue;
            const SourceJoint& free = free_source_[b]->joints.front();
            scene_.bodies[b].angular_velocity = free.angular;
            scene_.bodies[b].velocity = free.linear + free.angular.cross(scene_.bodies[b].position - free_source_[b]->origin);
        }
        propagate_velocities(scene_, joint_source_, parent_joint_);
        for (const SourceLoop& loop : tree_.loops) add_loop(loop);
        for (const SourceCoupling& coupling : tree_.couplings) add_coupling(coupling);
        if (!welded_to_world_.empty())
            scene_.notes.push_back("welded to the world, so part of the ground: " + joined(welded_to_world_));
        if (!outside_limits_.empty())
            scene_.unmapped.push_back({"joint limits that the start violates", outside_limits_,
                                       "the joint starts outside its range (give --position inside it)"});
        if (!wide_limits_.empty())
            scene_.unmapped.push_back({"joint limits at or beyond +-pi", wide_limits_,
                                       "a joint_stop measures the angle in (-pi, pi)"});
        if (!slide_passive_.empty())
            scene_.unmapped.push_back({"spring / damping on slide joints", slide_passive_,
                                       "no spring-damper along a prismatic joint's axis yet"});
        return scene_;
    }

private:
    // Source body i as scene bodies and joints; returns the scene body it became (-1: ground).
    int add_source_body(size_t i) {
        const SourceBody& body = tree_.bodies[i];
        const int parent = body.parent < 0 ? -1 : scene_.body_of_source[body.parent];
        const std::string what = element(tree_, body);
        const std::string name = body_names_.unique(body.name, "body" + std::to_string(i));
        if (body.joints.empty()) {  // welded to its parent
            if (parent < 0) {
                welded_to_world_.push_back(body.name);
            } else {
                merge(scene_.bodies[parent], body);
                scene_.bodies[parent].comment += ", merged with welded " + what;
            }
            return parent;
        }
        if (body.joints.front().kind == SourceJointKind::Free) {
            const int b = add_body(body, name, what + " (free joint '" + body.joints.front().name + "': no mbd joint)");
            free_source_[b] = &body;
            return b;
        }
        int previous = parent;
        const size_t n = body.joints.size();
        for (size_t k = 0; k + 1 < n; ++k) {  // the frames between the body's joints
            const SourceJoint& joint = body.joints[k];
            SourceBody frame = body;
            frame.mass = frame_mass_;
            frame.inertia = frame_mass_ * 0.01 * Mat3::Identity();
            frame.com = joint.point;
            frame.visuals.clear();  // the body's shapes go on the body, not on its frames
            const std::string joint_name = joint.name.empty() ? "joint" + std::to_string(k + 1) : joint.name;
            const int b = add_body(frame, body_names_.unique(body.name + "_" + joint_name + "_frame", ""),
                                   "frame between the joints of " + what + ", moved by its joint '" + joint.name + "'");
            scene_.bodies[b].frame = true;
            add_joint(body, joint, static_cast<int>(k), previous, b);
            previous = b;
        }
        const int b = add_body(body, name, what);
        add_joint(body, body.joints.back(), static_cast<int>(n - 1), previous, b);
        return b;
    }

    // A loop-closing constraint as a joint between the scene bodies its source bodies became.
    void add_loop(const SourceLoop& loop) {
        auto scene_body = [&](int source) { return source < 0 ? -1 : scene_.body_of_source[source]; };
        const int a = scene_body(loop.body_a), b = scene_body(loop.body_b);
        const std::string kind = loop.weld ? "weld" : tree_.format == "MJCF" ? "connect" : "joint";
        if (a == b) {  // both ends in one rigid body (welded, merged): the constraint holds by itself
            scene_.notes.push_back(tree_.format + " " + kind + " '" + loop.joint.name +
                                   "' joins two parts of one rigid body: nothing to constrain");
            return;
        }
        SceneJoint j;
        j.name = joint_names_.unique(loop.joint.name, kind);
        j.where = loop.joint.where;
        j.type = loop.weld ? "fixed" : joint_type(loop.joint.kind);
        j.kind = loop.joint.kind;
        j.parent = a;
        j.child = b;
        j.point = loop.joint.point;
        j.axis = loop.joint.axis.normalized();
        j.axis2 = loop.joint.axis2.normalized();
        j.pitch = loop.joint.pitch;
        j.comment = tree_.format + (tree_.format == "MJCF" ? " equality " : " ") + kind + " '" + loop.joint.name + "' (closes a loop)";
        scene_.joints.push_back(j);
    }

    // MuJoCo's armature I_a of a hinge or slide (kinetic energy 1/2 I_a qdot^2, I_a on the joint's diagonal
    // of the joint-space mass matrix) as a rotor: a disc of axial moment I_a pinned to the ground
    // (so it has no other motion) whose angle is coupled one to one to the joint's coordinate (rad per
    // rad, or rad per m). Its kinetic energy is then exactly 1/2 I_a qdot^2, and the coupling hands
    // -I_a qddot to the joint's coordinate, as MuJoCo's mass matrix does, whatever the parent's motion.
    void add_rotor(const SourceJoint& source, int joint) {
        if (source.armature < 0.0 || !std::isfinite(source.armature))
            throw InputError(source.where, tree_.format + " joint '" + source.name + "': armature " +
                                               format_number(source.armature) + " is not an inertia (give a number >= 0)");
        const SceneJoint j = scene_.joints[joint];  // a copy: scene_.joints grows below
        SceneBody rotor;
        rotor.name = body_names_.unique(j.name + "_rotor", "");
        rotor.where = source.where;
        rotor.comment = "rotor of the armature " + format_number(source.armature) + " of " + tree_.format + " joint '" +
                        source.name + "', pinned to the ground, its angle coupled to the joint's coordinate";
        rotor.mass = source.armature / 0.01;  // a disc of radius 0.14 m; pinned, so its mass does nothing
        rotor.position = j.point;
        rotor.rotation.col(2) = j.axis;
        rotor.rotation.col(0) = any_perpendicular(j.axis);
        rotor.rotation.col(1) = j.axis.cross(rotor.rotation.col(0));
        rotor.inertia = Vec3(0.5, 0.5, 1.0).asDiagonal() * source.armature;
        rotor.frame = true;  // not a body of the source
        scene_.bodies.push_back(rotor);
        parent_joint_.push_back(-1);
        free_source_.push_back(nullptr);
        const int b = static_cast<int>(scene_.bodies.size()) - 1;

        SourceJoint& pin = rotor_sources_.emplace_back(source);  // its rate is the joint's
        pin.kind = SourceJointKind::Hinge;
        SceneJoint p = j;
        p.name = joint_names_.unique(j.name + "_rotor_pin", "");
        p.type = "revolute";
        p.kind = SourceJointKind::Hinge;
        p.parent = -1;
        p.child = b;
        p.comment = "pin of the rotor of " + tree_.format + " joint '" + source.name + "'";
        scene_.joints.push_back(p);
        joint_source_.push_back(&pin);
        parent_joint_[b] = static_cast<int>(scene_.joints.size()) - 1;

        SceneCoupling c;
        c.name = joint_names_.unique(j.name + "_armature", "");
        c.where = source.where;
        c.comment = "armature of " + tree_.format + " joint '" + source.name + "': the rotor turns with its coordinate";
        c.follower = parent_joint_[b];
        c.leader = joint;
        c.follower_start = c.leader_start = source.position;
        scene_.couplings.push_back(c);
    }

    // The scene joint of the source joint named `name` (InputError naming the coupling when the file has none
    // or it has no single coordinate).
    int coupled_joint(const SourceCoupling& c, const std::string& name, const char* role) const {
        const auto it = joint_of_source_name_.find(name);
        if (it == joint_of_source_name_.end())
            throw InputError(c.where, c.what + ": its " + role + " joint '" + name + "' is not a joint of the " + tree_.format +
                                          " file (check the joint name)");
        const SourceJointKind kind = joint_source_[it->second]->kind;
        if (kind != SourceJointKind::Hinge && kind != SourceJointKind::Slide && kind != SourceJointKind::Screw)
            throw InputError(c.where, c.what + ": its " + role + " joint '" + name + "' is a " + joint_type(kind) +
                                          " joint; only hinge, slide and screw joints have the one coordinate a coupling ties");
        return it->second;
    }

    // q_follower = multiplier q_leader + offset as a coordinate_coupling joint; the start must satisfy it.
    void add_coupling(const SourceCoupling& c) {
        SceneCoupling out;
        out.follower = coupled_joint(c, c.follower, "follower");
        out.leader = coupled_joint(c, c.leader, "leader");
        if (out.follower == out.leader)
            throw InputError(c.where, c.what + ": it couples joint '" + c.follower + "' to itself");
        out.follower_start = joint_source_[out.follower]->position;
        out.leader_start = joint_source_[out.leader]->position;
        const double wanted = c.multiplier * out.leader_start + c.offset;
        if (std::abs(out.follower_start - wanted) > 1e-9 * (1.0 + std::abs(wanted)))
            throw InputError(c.where, c.what + ": the start does not satisfy it: joint '" + c.follower + "' is at " +
                                          format_number(out.follower_start) + ", the coupling wants " +
                                          format_number(wanted) + " (give --position " + c.follower + "=" +
                                          format_number(wanted, 17) + ")");
        out.name = joint_names_.unique(c.name + "_coupling", "");
        out.where = c.where;
        out.comment = c.what + ": " + c.follower + " = " + format_number(c.multiplier) + " " + c.leader + " + " +
                      format_number(c.offset);
        out.multiplier = c.multiplier;
        out.offset = c.offset;
        scene_.couplings.push_back(out);
    }

    // The limits of a hinge or slide as a joint_stop. The stop's angle is zero at the scene's
    // start like the source's coordinate; its travel is measured from the joint's point to the
    // child's mass centre, so the limits move by that distance at the start.
    void add_stop(const SceneJoint& joint, const SourceJoint& source) {
        if (source.lower > 0.0 || source.upper < 0.0) {  // the stop would throw the joint back at once
            outside_limits_.push_back(joint.name);
            return;
        }
        SceneStop stop;
        stop.name = force_names_.unique(joint.name + "_limits", "");
        stop.where = source.where;
        stop.parent = joint.parent;
        stop.child = joint.child;
        stop.point = joint.point;
        stop.axis = joint.axis;
        stop.travel = source.kind == SourceJointKind::Slide;
        const double start = stop.travel ? joint.axis.dot(scene_.bodies[joint.child].position - joint.point) : 0.0;
        stop.lower = source.lower + start;
        stop.upper = source.upper + start;
        stop.stiffness = source.stop_stiffness;
        // a limit at +-1e16 is none (SDF's convention, and mbd export's for a side without a stop)
        stop.has_lower = source.lower > -kNoLimitBeyond;
        stop.has_upper = source.upper < kNoLimitBeyond;
        if (!stop.travel) {  // mbd's spatial angle lies in (-pi, pi): a limit beyond cannot be met there
            const bool wide_lower = stop.has_lower && !(stop.lower > -M_PI), wide_upper = stop.has_upper && !(stop.upper < M_PI);
            stop.has_lower = stop.has_lower && !wide_lower;
            stop.has_upper = stop.has_upper && !wide_upper;
            if (wide_lower || wide_upper)
                wide_limits_.push_back(joint.name + (stop.has_lower || stop.has_upper ? " (one side)" : ""));
        }
        if (stop.has_lower || stop.has_upper) scene_.stops.push_back(stop);
    }

    int add_body(const SourceBody& source, const std::string& name, const std::string& comment) {
        SceneBody b;
        b.name = name;
        b.where = source.where;
        b.comment = comment;
        b.mass = source.mass;
        b.inertia = source.inertia;
        b.position = source.com;
        b.rotation = source.rotation;
        b.visuals = source.visuals;
        scene_.bodies.push_back(b);
        parent_joint_.push_back(-1);
        free_source_.push_back(nullptr);
        return static_cast<int>(scene_.bodies.size()) - 1;
    }

    void add_joint(const SourceBody& body, const SourceJoint& source, int index, int parent, int child) {
        SceneJoint j;
        j.name = joint_names_.unique(source.name, body.name + "_joint" + std::to_string(index + 1));
        j.where = source.where;
        j.type = joint_type(source.kind);
        j.kind = source.kind;
        j.parent = parent;
        j.child = child;
        j.point = source.point;
        j.axis = source.axis.normalized();
        j.axis2 = source.axis2.normalized();
        j.pitch = source.pitch;
        scene_.joints.push_back(j);
        joint_source_.push_back(&source);
        if (!source.name.empty()) joint_of_source_name_.emplace(source.name, static_cast<int>(scene_.joints.size()) - 1);
        parent_joint_[child] = static_cast<int>(scene_.joints.size()) - 1;
        if (source.limited) add_stop(j, source);
        if (source.armature != 0.0) add_rotor(source, static_cast<int>(scene_.joints.size()) - 1);
        if (source.stiffness == 0.0 && source.damping == 0.0) return;
        if (source.kind != SourceJointKind::Hinge) {
            slide_passive_.push_back(j.name);
            return;
        }
        SceneForce f;
        f.name = force_names_.unique(j.name + "_spring_damper", "");
        f.where = source.where;
        f.parent = parent;
        f.child = child;
        f.point = j.point;
        f.axis = j.axis;
        f.stiffness = source.stiffness;
        f.damping = source.damping;
        f.rest_angle = source.spring_reference;
        scene_.forces.push_back(f);
    }

    const SourceTree& tree_;
    ImportedScene scene_;
    double frame_mass_ = 0.0;
    Names body_names_, joint_names_, force_names_;
    std::vector<const SourceJoint*> joint_source_;  // per scene joint of the tree
    std::deque<SourceJoint> rotor_sources_;         // the pins of the armature rotors (stable addresses)
    std::map<std::string, int> joint_of_source_name_;  // scene joint of each named source joint
    std::vector<int> parent_joint_;                 // per scene body: the joint to its parent, -1 none
    std::vector<const SourceBody*> free_source_;    // per scene body: the source of a free body
    std::vector<std::string> welded_to_world_, slide_passive_, wide_limits_, outside_limits_;
};

}  // namespace

ImportedScene build_scene(const SourceTree& tree) { return SceneBuilder(tree).build(); }

std::string unmapped_summary(const std::vector<Unmapped>& unmapped) {
    std::string out;
    for (const Unmapped& u : unmapped) {
        if (u.names.empty()) continue;
        if (!out.empty()) out += "; ";
        out += std::to_string(u.names.size()) + " " + u.kind + " (" + joined(u.names) + ")";
        if (!u.note.empty()) out += ": " + u.note;
    }
    return out;
}

}  // namespace mbd::import
