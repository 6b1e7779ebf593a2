// Per-step cost of the augmented formulation's right-hand side (book Eq. 6.141 via the
// Schur complement) against the number of bodies, for a planar chain of N pendulum
// links (revolute joints, gravity), dense vs sparse linear algebra. Reports the median
// time of one rhs evaluation and the fitted log-log slope (time ~ N^slope).
//   bench_augmented [max_bodies=10000] [max_dense=1000]
// Results and the chosen dense/sparse threshold: docs/benchmarks.md.
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
#include <string>
#include <vector>

#include "bench_stats.hpp"

namespace {

// A chain of n links of 0.1 m, 1 kg, laid out along +x from the ground pivot.
std::string chain_scene(int n) {
    std::string s = "name: chain\ndimension: planar\ngravity: [0, -9.81]\nbodies:\n";
    const double l = 0.1;
    for (int k = 0; k < n; ++k)
        s += "  - {name: b" + std::to_string(k) + ", mass: 1, inertia: 0.000833333, position: [" +
             std::to_string(l * (k + 0.5)) + ", 0]}\n";
    s += "joints:\n";
    for (int k = 0; k < n; ++k)
        s += "  - {name: j" + std::to_string(k) + ", type: revolute, bodies: [" +
             (k == 0 ? std::string("ground") : "b" + std::to_string(k - 1)) + ", b" + std::to_string(k) +
             "], point: [" + std::to_string(l * k) + ", 0]}\n";
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    mbd::declare_application_scene_sections();  // scenes/bench keep their `bench:`
    const int max_bodies = argc > 1 ? std::atoi(argv[1]) : 10000;
    const int max_dense = argc > 2 ? std::atoi(argv[2]) : 1000;
    const std::vector<int> sizes{10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000};
    mbd::Registry registry;
    const auto dir = std::filesystem::temp_directory_path();
    std::vector<double> nd, td, ns, ts;
    std::printf("%8s %8s %14s %14s %10s\n", "bodies", "nv", "dense [s]", "sparse [s]", "reps");
    for (int n : sizes) {
        if (n > max_bodies) break;
        const auto path = dir / ("mbd_bench_chain_" + std::to_string(n) + ".yaml");
        std::ofstream(path) << chain_scene(n);
        const mbd::Model model = mbd::load_scene(path.string(), registry);
        std::filesystem::remove(path);
        mbd::ModelSystem system(model);
        mbd::State state = system.initial_state();
        state.v.setConstant(0.1);
        system.consistent_velocities(state);
        double result[2] = {NAN, NAN};
        int reps_used = 0;
        for (int sparse = 0; sparse < 2; ++sparse) {
            if (!sparse && n > max_dense) continue;
            mbd::FormulationSpec spec{"augmented", "augmented", {}};
            auto f = registry.create_formulation(spec, "bench");
            mbd::FormulationOptions options;
            options.algebra = sparse ? mbd::LinearAlgebra::Sparse : mbd::LinearAlgebra::Dense;
            f->bind(system, options);
            Eigen::VectorXd y, ydot;
            f->to_ode(state, y);
            f->rhs(0.0, y, ydot);  // warm-up
            std::vector<double> times;
            const auto start = std::chrono::steady_clock::now();
            for (int rep = 0; rep < 200; ++rep) {
                const auto t0 = std::chrono::steady_clock::now();
                f->rhs(0.0, y, ydot);
                times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
                if (rep >= 4 && std::chrono::steady_clock::now() - start > std::chrono::seconds(3)) break;
            }
            result[sparse] = median(times);
            reps_used = std::max(reps_used, static_cast<int>(times.size()));
            (sparse ? ns : nd).push_back(n);
            (sparse ? ts : td).push_back(result[sparse]);
        }
        std::printf("%8d %8d %14.4e %14.4e %10d\n", n, system.nv(), result[0], result[1], reps_used);
        std::fflush(stdout);
    }
    // slopes over the sizes where the cost is not dominated by fixed overheads (n >= 100)
    auto tail_slope = [](const std::vector<double>& n, const std::vector<double>& t) {
        std::vector<double> a, b;
        for (size_t k = 0; k < n.size(); ++k)
            if (n[k] >= 100) a.push_back(n[k]), b.push_back(t[k]);
        return a.size() >= 2 ? slope(a, b) : NAN;
    };
    std::printf("log-log slope (N >= 100): dense %.2f, sparse %.2f\n", tail_slope(nd, td), tail_slope(ns, ts));
    for (size_t k = 0; k < nd.size() && k < ns.size(); ++k)
        if (ts[k] < td[k]) {
            std::printf("sparse is faster from %g bodies (%g velocity coordinates) on\n", nd[k], 3 * nd[k]);
            break;
        }
    return 0;
}
