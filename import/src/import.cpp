// The import layer's entry points (import.hpp).
#include <mbd/import/import.hpp>

#include <mbd/import/mjcf_reader.hpp>
#include <mbd/import/model_format.hpp>
#include <mbd/import/scene_writer.hpp>
#include <mbd/import/sdf_reader.hpp>
#include <mbd/import/urdf_reader.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/params.hpp>  // InputError

#include <Eigen/Geometry>

#include <cmath>

namespace mbd::import {

namespace {

Vec3 three(const std::vector<double>& v, size_t at) { return Vec3(v[at], v[at + 1], v[at + 2]); }

size_t velocity_count(SourceJointKind kind) {
    switch (kind) {
        case SourceJointKind::Hinge:
        case SourceJointKind::Slide:
        case SourceJointKind::Screw: return 1;
        case SourceJointKind::Universal: return 2;
        case SourceJointKind::Ball: return 3;
        case SourceJointKind::Free: return 6;
        case SourceJointKind::Planar: break;
    }
    return 0;
}

// The joint named `name` and its body (InputError naming the file when there is none).
std::pair<SourceBody*, size_t> find_joint(SourceTree& tree, const std::string& name, const char* what) {
    for (SourceBody& body : tree.bodies)
        for (size_t k = 0; k < body.joints.size(); ++k)
            if (body.joints[k].name == name) return {&body, k};
    throw InputError(tree.file, std::string("an initial ") + what + " is given for joint '" + name + "', which the " +
                                    tree.format + " file does not have");
}

// A rigid motion: x -> point + turn (x - point) + shift.
struct Motion {
    Vec3 point, shift;
    Mat3 turn;
    Vec3 moved(const Vec3& x) const { return point + turn * (x - point) + shift; }
};

void move_body(SourceBody& body, const Motion& m, size_t first_joint) {
    for (VisualShape& v : body.visuals) {
        v.position = m.moved(v.position);
        v.rotation = m.turn * v.rotation;
    }
    body.origin = m.moved(body.origin);
    body.com = m.moved(body.com);
    body.rotation = m.turn * body.rotation;
    for (size_t k = first_joint; k < body.joints.size(); ++k) {
        SourceJoint& j = body.joints[k];
        j.point = m.moved(j.point);
        j.axis = m.turn * j.axis;
        j.axis2 = m.turn * j.axis2;
    }
}

// Moves body `index` (its joints from `first_joint` on) and all its descendants by `m`, and the loops
// that lie in that subtree; a loop with one end inside is an InputError naming `what`.
void move_subtree(SourceTree& tree, int index, const Motion& m, size_t first_joint, const std::string& where,
                  const std::string& what) {
    std::vector<bool> moved(tree.bodies.size(), false);  // the subtree (parents come first)
    moved[index] = true;
    move_body(tree.bodies[index], m, first_joint);
    for (size_t b = index + 1; b < tree.bodies.size(); ++b) {
        const int parent = tree.bodies[b].parent;
        if (parent < 0 || !moved[parent]) continue;
        moved[b] = true;
        move_body(tree.bodies[b], m, 0);
    }
    for (SourceLoop& loop : tree.loops) {  // a loop moves with the subtree only if it lies in it
        const bool a = loop.body_a >= 0 && moved[loop.body_a], b = loop.body_b >= 0 && moved[loop.body_b];
        if (a != b)
            throw InputError(where, what + " lies in the closed loop of '" + loop.joint.name +
                                        "': its position cannot be set alone (the loop would open)");
        if (a) loop.joint.point = m.moved(loop.joint.point);
    }
}

// A keyframe's start: its free bodies placed, its joint positions and velocities put into `options`
// where the options do not give them.
void apply_keyframe(SourceTree& tree, ImportOptions& options) {
    if (options.keyframe.empty()) return;
    const SourceKeyframe* key = nullptr;
    std::string names;
    for (const SourceKeyframe& k : tree.keyframes) {
        if (k.name == options.keyframe) key = &k;
        names += (names.empty() ? "" : ", ") + k.name;
    }
    if (!key)
        throw InputError(tree.file, "--keyframe " + options.keyframe + ": the " + tree.format + " file has no keyframe of that name (" +
                                        (names.empty() ? std::string("it has none; only MJCF <key> elements are keyframes")
                                                       : "it has: " + names) + ")");
    if (!key->moved_balls.empty())
        throw InputError(tree.file, "keyframe '" + key->name + "' turns ball joint '" + key->moved_balls.front() +
                                        "' from qpos0; a ball joint's initial position cannot be set yet");
    for (const auto& [name, pose] : key->free_poses) {
        auto [owner, k] = find_joint(tree, name, "pose (keyframe)");
        const Mat3 turn = rotation_from_euler_parameters(pose.second) * owner->rotation.transpose();
        move_subtree(tree, static_cast<int>(owner - tree.bodies.data()), Motion{owner->origin, pose.first - owner->origin, turn}, 0,
                     owner->joints[k].where, "free joint '" + name + "'");
    }
    for (const auto& [name, q] : key->positions) options.joint_positions.emplace(name, q);
    for (const auto& [name, v] : key->velocities) options.joint_velocities.emplace(name, v);
}

}  // namespace

void apply_joint_positions(SourceTree& tree, const ImportOptions& options) {
    for (const auto& [name, q] : options.joint_positions) {
        auto [owner, k] = find_joint(tree, name, "position");
        SourceJoint& joint = owner->joints[k];
        Motion m{joint.point, Vec3::Zero(), Mat3::Identity()};
        switch (joint.kind) {
            case SourceJointKind::Hinge: m.turn = Eigen::AngleAxisd(q, joint.axis).toRotationMatrix(); break;
            case SourceJointKind::Slide: m.shift = q * joint.axis; break;
            case SourceJointKind::Screw:
                m.turn = Eigen::AngleAxisd(q, joint.axis).toRotationMatrix();
                m.shift = joint.pitch / (2.0 * M_PI) * q * joint.axis;
                break;
            default:
                throw InputError(joint.where, "joint '" + name + "': an initial position can be given to hinge, slide "
                                              "and screw joints only");
        }
        joint.position += q;
        joint.spring_reference -= q;  // mbd's coordinates are zero at the scene's start
        joint.lower -= q;
        joint.upper -= q;
        move_subtree(tree, static_cast<int>(owner - tree.bodies.data()), m, k + 1, joint.where, "joint '" + name + "'");
    }
}

void apply_joint_velocities(SourceTree& tree, const ImportOptions& options) {
    for (const auto& [name, values] : options.joint_velocities) {
        auto [owner, k] = find_joint(tree, name, "velocity");
        SourceJoint* found = &owner->joints[k];
        const size_t count = velocity_count(found->kind);
        if (count == 0 || values.size() != count)
            throw InputError(found->where, "joint '" + name + "': " +
                                               (count == 0 ? std::string("an initial velocity of a planar joint cannot be given yet")
                                                           : "its initial velocity has " + std::to_string(count) +
                                                                 " numbers, " + std::to_string(values.size()) + " given"));
        if (count == 1) found->rate = values[0];
        if (count == 2) found->angular = values[0] * found->axis + values[1] * found->axis2;
        if (count == 3) found->angular = owner->rotation * three(values, 0);
        if (count == 6) {
            found->linear = three(values, 0);
            found->angular = owner->rotation * three(values, 3);
        }
    }
}

SourceTree read_model_file(const std::filesystem::path& file) {
    switch (detect_format(file)) {
        case ModelFormat::Mjcf: return read_mjcf(file);
        case ModelFormat::Urdf: return read_urdf(file);
        case ModelFormat::Sdf: return read_sdf(file);
        case ModelFormat::Scene: break;
    }
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error))
        throw InputError(file.string(), "cannot read the model file: it is not a file that exists");
    throw InputError(file.string(), "not an MJCF, URDF or SDF file (no <mujoco>, <robot> or <sdf> root element): it is read as "
                                    "an mbd scene, which needs no import");
}

ImportedScene import_model(const std::filesystem::path& file, const ImportOptions& given) {
    SourceTree tree = read_model_file(file);
    ImportOptions options = given;
    apply_keyframe(tree, options);
    apply_joint_positions(tree, options);
    apply_joint_velocities(tree, options);
    return build_scene(tree);
}

Model load_scene_or_model(const std::filesystem::path& file, Registry& registry,
                          const std::function<void(const std::string&)>& warn) {
    if (detect_format(file) == ModelFormat::Scene) return load_scene(file, registry);
    const ImportedScene scene = import_model(file);
    const std::string missing = unmapped_summary(scene.unmapped);
    if (!missing.empty() && warn) warn(file.string() + ": not imported: " + missing);
    return load_scene_text(scene_yaml(scene), file.string() + " (imported)", registry);
}

}  // namespace mbd::import
