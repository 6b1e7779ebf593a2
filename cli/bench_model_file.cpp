// The default benchmark of a model file (bench_model_file.hpp).
#include "bench_model_file.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/model_format.hpp>
#include <mbd/import/scene_writer.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <map>

namespace mbd {

namespace {

// The documented initial velocities by joint name (bench_model_file.hpp); unnamed joints rest.
import::ImportOptions documented_velocities(const import::SourceTree& tree) {
    import::ImportOptions options;
    int scalar = 0;
    for (const import::SourceBody& body : tree.bodies)
        for (const import::SourceJoint& joint : body.joints) {
            const bool one = joint.kind == import::SourceJointKind::Hinge || joint.kind == import::SourceJointKind::Slide;
            std::vector<double> v;
            if (one) v = {(scalar % 2 ? -1.0 : 1.0) * (1.0 + 0.1 * scalar)}, ++scalar;
            if (joint.kind == import::SourceJointKind::Free) v = {0.3, -0.2, 1.0, 0.5, -0.4, 0.8};
            if (!v.empty() && !joint.name.empty()) options.joint_velocities[joint.name] = v;
        }
    return options;
}

// The peers' form of the velocities: JOINT=V[/V...], comma-separated ("-" for none).
std::string velocity_argument(const import::ImportOptions& options) {
    std::string out;
    for (const auto& [name, values] : options.joint_velocities) {
        out += (out.empty() ? "" : ",") + name + "=";
        for (size_t k = 0; k < values.size(); ++k) out += (k ? "/" : "") + format_number(values[k], 17);
    }
    return out.empty() ? "-" : out;
}

// Bodies that are one body of the file: not a frame body, and no other source body with mass
// merged into them (their mass centre is then the same point in every engine).
std::vector<std::string> measured_bodies(const import::SourceTree& tree, const import::ImportedScene& scene) {
    std::map<int, double> merged_mass;  // scene body -> mass of the source bodies beyond the first
    std::map<int, int> sources;
    for (size_t s = 0; s < scene.body_of_source.size() && s < tree.bodies.size(); ++s) {
        const int b = scene.body_of_source[s];
        if (b < 0) continue;
        if (sources[b]++ > 0 || scene.bodies[b].name != tree.bodies[s].name) merged_mass[b] += tree.bodies[s].mass;
    }
    std::vector<std::string> out;
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
        const int i = static_cast<int>(b);
        if (scene.bodies[b].frame || sources[i] == 0 || merged_mass[i] > 0.0) continue;
        out.push_back(scene.bodies[b].name);
    }
    return out;
}

std::vector<double> decades(double from, double to, int per_decade) {
    std::vector<double> out;
    const int n = static_cast<int>(std::lround(std::log10(from / to) * per_decade));
    for (int k = 0; k <= n; ++k) out.push_back(from * std::pow(10.0, -static_cast<double>(k) / per_decade));
    return out;
}

}  // namespace

ModelFileBench model_file_bench(const std::filesystem::path& file, Registry& registry) {
    import::SourceTree tree = import::read_model_file(file);
    const import::ImportOptions velocities = documented_velocities(tree);
    import::apply_joint_velocities(tree, velocities);
    const import::ImportedScene scene = import::build_scene(tree);
    ModelFileBench out{load_scene_text(import::scene_yaml(scene), file.string() + " (imported)", registry), {}};
    BenchSpec& spec = out.spec;
    spec.scene = file.string();
    spec.name = file.filename().string();
    spec.t_end = 1.0;
    spec.output_step = 0.01;
    spec.measure.bodies = measured_bodies(tree, scene);
    if (spec.measure.bodies.empty())
        throw InputError(file.string(), "bench: the model has no body of its own to measure (every body is merged or welded)");
    spec.measure.points.assign(spec.measure.bodies.size(), Eigen::Vector3d::Zero());
    spec.reference.kind = "tight_run";
    spec.reference.formulation = "embedding";
    spec.reference.integrator = "dop853";
    spec.reference.cross_check = "augmented";
    spec.reference.tolerance = 1e-12;
    const std::string formulation = automatic_method(out.model, spec.t_end).formulation;
    spec.runs.push_back({formulation, "dopri5", decades(1e-3, 1e-11, 1), {}});
    spec.runs.push_back({formulation, "dop853", decades(1e-4, 1e-12, 1), {}});
    spec.peer_model = std::filesystem::absolute(file).lexically_normal().string();
    std::string bodies;
    for (const std::string& b : spec.measure.bodies) bodies += (bodies.empty() ? "" : ",") + b;
    spec.peer_arguments = {bodies, velocity_argument(velocities)};
    const import::ModelFormat format = import::detect_format(file);
    if (format == import::ModelFormat::Mjcf || format == import::ModelFormat::Urdf)
        spec.peers.push_back({"mujoco", "rk4", {}, decades(1e-2, 1e-5, 2)});
    if (format == import::ModelFormat::Urdf) {  // DART's World (first order) and its dynamics under RK4
        spec.peers.push_back({"dart", "euler", {}, decades(1e-2, 1e-5, 2)});
        spec.peers.push_back({"dart", "rk4", {}, decades(1e-2, 1e-5, 2)});
    }
    return out;
}

}  // namespace mbd
