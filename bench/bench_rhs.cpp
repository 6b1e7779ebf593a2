// Cost of one right-hand side y' = f(t, y) of every formulation on given scenes: each
// formulation bound as `mbd simulate` binds it (dense below 30 velocity coordinates, sparse
// above), at the scene's assembled initial state; the median over batches of the time per
// evaluation. The same source builds against older trees, for before/after comparisons
// (docs/benchmarks.md).
//   bench_rhs SCENE.yaml... [--formulations a,b,...]
// A formulation may carry one key: NAME:KEY=VALUE (e.g. embedding:path=dense).
#include <mbd/app/scene_sections.hpp>
#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "bench_stats.hpp"

namespace {

double rhs_seconds(mbd::Formulation& f, const Eigen::VectorXd& y) {
    Eigen::VectorXd ydot;
    return median_seconds_per_call([&] { f.rhs(0.0, y, ydot); });
}

}  // namespace

int main(int argc, char** argv) {
    mbd::declare_application_scene_sections();  // scenes/bench keep their `bench:`
    std::vector<std::string> scenes, formulations = {"augmented", "embedding", "amalgamated", "hamiltonian"};
    for (int k = 1; k < argc; ++k) {
        if (std::strcmp(argv[k], "--formulations") == 0 && k + 1 < argc) {
            formulations.clear();
            std::stringstream list(argv[++k]);
            for (std::string name; std::getline(list, name, ',');) formulations.push_back(name);
        } else {
            scenes.emplace_back(argv[k]);
        }
    }
    if (scenes.empty()) {
        std::fprintf(stderr, "usage: bench_rhs SCENE.yaml... [--formulations a,b,...]\n");
        return 2;
    }
    mbd::Registry registry;
    std::printf("%-24s %-20s %6s %14s\n", "scene", "formulation", "nv", "rhs [us]");
    for (const std::string& path : scenes) {
        const mbd::Model model = mbd::load_scene(path, registry);
        const std::string name = path.substr(path.find_last_of('/') + 1);
        for (const std::string& type : formulations) {
            try {
                mbd::ModelSystem system(model);
                // NAME or NAME:KEY=VALUE
                const size_t colon = type.find(':'), equals = type.find('=');
                const std::string base = type.substr(0, colon);
                mbd::Param node;
                node.kind = mbd::Param::Kind::Map;
                if (colon != std::string::npos && equals != std::string::npos) {
                    mbd::Param value;
                    value.kind = mbd::Param::Kind::Scalar;
                    value.text = type.substr(equals + 1);
                    node.fields[type.substr(colon + 1, equals - colon - 1)] = value;
                }
                mbd::FormulationSpec spec{base, base, mbd::Params("formulation '" + base + "'", &node)};
                auto f = registry.create_formulation(spec, "bench");
                mbd::FormulationOptions options;
                options.sparse_threshold = 30;  // as mbd simulate
                f->bind(system, options);
                mbd::State state = system.initial_state();
                state.t = 0.0;
                system.assemble(state, true);
                system.consistent_velocities(state, true);
                Eigen::VectorXd y;
                f->to_ode(state, y);
                f->project(0.0, y);
                std::printf("%-24s %-20s %6d %14.3f\n", name.c_str(), type.c_str(), model.nv(), 1e6 * rhs_seconds(*f, y));
            } catch (const std::exception& e) {
                std::printf("%-24s %-20s %6d %14s  (%s)\n", name.c_str(), type.c_str(), model.nv(), "failed", e.what());
            }
            std::fflush(stdout);
        }
    }
    return 0;
}
