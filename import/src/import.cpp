// The import layer's entry points (import.hpp).
#include <mbd/import/import.hpp>

#include <mbd/import/mjcf_reader.hpp>
#include <mbd/import/model_format.hpp>
#include <mbd/import/scene_writer.hpp>
#include <mbd/import/sdf_reader.hpp>
#include <mbd/import/urdf_reader.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/params.hpp>  // InputError

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

}  // namespace

void apply_joint_velocities(SourceTree& tree, const ImportOptions& options) {
    for (const auto& [name, values] : options.joint_velocities) {
        SourceJoint* found = nullptr;
        const SourceBody* owner = nullptr;
        for (SourceBody& body : tree.bodies)
            for (SourceJoint& joint : body.joints)
                if (joint.name == name) found = &joint, owner = &body;
        if (!found) throw InputError(tree.file, "an initial velocity is given for joint '" + name + "', which the " +
                                                    tree.format + " file does not have");
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

ImportedScene import_model(const std::filesystem::path& file, const ImportOptions& options) {
    SourceTree tree = read_model_file(file);
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
