// Per-step cost of the embedding formulation's right-hand side against the number of
// links, recursive (joint coordinates, articulated-body algorithm) vs dense (absolute
// coordinates, partitioned J, B^T M B of book Eq. 6.95), for a planar chain (revolute
// joints) and a spatial chain (revolute joints with alternating axes, every third one
// spherical). Reports the median time of one rhs evaluation and the fitted log-log slopes
// (time ~ N^slope). Results: docs/benchmarks.md, section "Embedding".
//   bench_embedding [max_links=10000] [max_dense=200] [min_links=10]
#include <mbd/app/scene_sections.hpp>
#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_stats.hpp"

namespace {

std::string chain_scene(int n, bool spatial) {
    std::ostringstream s;
    const double l = 0.1;
    s << "name: chain\ndimension: " << (spatial ? "spatial" : "planar") << "\ngravity: "
      << (spatial ? "[0, 0, -9.81]" : "[0, -9.81]") << "\nbodies:\n";
    for (int k = 0; k < n; ++k) {
        s << "  - {name: b" << k << ", mass: 1, inertia: " << (spatial ? "[0.0001, 0.000833, 0.000833]" : "0.000833")
          << ", position: [" << l * (k + 0.5) << ", 0" << (spatial ? ", 0" : "") << "]}\n";
    }
    s << "joints:\n";
    for (int k = 0; k < n; ++k) {
        const bool ball = spatial && k % 3 == 2;
        s << "  - {name: j" << k << ", type: " << (ball ? "spherical" : "revolute") << ", bodies: ["
          << (k == 0 ? std::string("ground") : "b" + std::to_string(k - 1)) << ", b" << k << "], point: [" << l * k
          << ", 0" << (spatial ? ", 0" : "") << "]";
        if (spatial && !ball) s << ", axis: " << (k % 2 ? "[0, 1, 0]" : "[0, 0, 1]");
        s << "}\n";
    }
    return s.str();
}

// median seconds per rhs evaluation
double time_rhs(mbd::Registry& registry, const mbd::Model& model, const std::string& path) {
    mbd::ModelSystem system(model);
    mbd::Param node;
    node.kind = mbd::Param::Kind::Map;
    for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{{"path", path}, {"log", "false"}}) {
        mbd::Param p;
        p.text = v;
        node.fields[k] = p;
    }
    mbd::FormulationSpec spec{"embedding", "embedding", mbd::Params("formulation 'embedding'", &node)};
    auto formulation = registry.create_formulation(spec, "bench");
    formulation->bind(system, mbd::FormulationOptions{});
    mbd::State state = system.initial_state();
    state.t = 0.0;
    system.assemble(state, true);
    system.consistent_velocities(state, true);
    Eigen::VectorXd y, ydot;
    formulation->to_ode(state, y);
    formulation->rhs(0.0, y, ydot);  // warm up
    std::vector<double> samples;
    const auto start = std::chrono::steady_clock::now();
    while (samples.size() < 5 ||
           (samples.size() < 200 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 1.0)) {
        const auto t0 = std::chrono::steady_clock::now();
        formulation->rhs(0.0, y, ydot);
        samples.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return median(samples);
}

}  // namespace

int main(int argc, char** argv) {
    mbd::declare_application_scene_sections();  // scenes/bench keep their `bench:`
    const int max_links = argc > 1 ? std::atoi(argv[1]) : 10000;
    const int max_dense = argc > 2 ? std::atoi(argv[2]) : 200;
    const int min_links = argc > 3 ? std::atoi(argv[3]) : 10;
    const std::vector<int> sizes{10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000};
    mbd::Registry registry;
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mbd-bench-embedding";
    std::filesystem::create_directories(dir);
    for (bool spatial : {false, true}) {
        std::vector<double> n_rec, t_rec, n_den, t_den;
        std::printf("%s chain\n%8s %16s %16s\n", spatial ? "spatial" : "planar", "links", "recursive [us]", "dense [us]");
        for (int n : sizes) {
            if (n > max_links) break;
            if (n < min_links) continue;
            const std::filesystem::path file = dir / ("chain-" + std::to_string(n) + ".yaml");
            std::ofstream(file) << chain_scene(n, spatial);
            const mbd::Model model = mbd::load_scene(file.string(), registry);
            const double tr = time_rhs(registry, model, "recursive");
            n_rec.push_back(n);
            t_rec.push_back(tr);
            double td = NAN;
            if (n <= max_dense) {
                td = time_rhs(registry, model, "dense");
                n_den.push_back(n);
                t_den.push_back(td);
            }
            std::printf("%8d %16.2f %16.2f\n", n, tr * 1e6, td * 1e6);
            std::fflush(stdout);
        }
        std::printf("log-log slope: recursive %.3f", slope(n_rec, t_rec));
        if (n_den.size() > 1) std::printf(", dense %.3f", slope(n_den, t_den));
        std::printf("\n\n");
    }
    return 0;
}
