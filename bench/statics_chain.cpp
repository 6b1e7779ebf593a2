// Benchmark (not a test): statics of a planar chain of N bodies (default 1000)
// hanging from the ground by revolute joints, with gravity and a torsion spring
// at every joint, solved by the Ipopt statics plugin (potential objective, exact
// sparse Hessian). Usage: mbd_bench_statics_chain [N]. Results: docs/benchmarks.md.
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/statics_analysis.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>

int main(int argc, char** argv) {
    const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
    const double l = 0.1, m = 0.1, J = m * l * l / 12, k = 2000.0;
    std::ostringstream s;
    s << "dimension: planar\ngravity: [0, -9.81]\nbodies:\n";
    for (int i = 0; i < n; ++i)
        s << "  - {name: b" << i << ", mass: " << m << ", inertia: " << J << ", position: [" << (i + 0.5) * l << ", 0]}\n";
    s << "joints:\n";
    for (int i = 0; i < n; ++i)
        s << "  - {name: j" << i << ", type: revolute, bodies: [" << (i ? "b" + std::to_string(i - 1) : "ground")
          << ", b" << i << "], point: [" << i * l << ", 0]}\n";
    s << "forces:\n";
    for (int i = 0; i < n; ++i)
        s << "  - {name: k" << i << ", type: rotational_spring_damper, bodies: [" << (i ? "b" + std::to_string(i - 1) : "ground")
          << ", b" << i << "], stiffness: " << k * n << ", rest_angle: 0}\n";
    mbd::Registry registry;
    const mbd::Model model = mbd::load_scene_text(s.str(), "chain.yaml", registry);
    mbd::StaticsOptions options;
    const auto t0 = std::chrono::steady_clock::now();
    const mbd::StaticsReport rep = mbd::run_statics(model, registry, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("chain of %d bodies: converged %s, status %s, %d iterations, residual %.3e, stability %s, "
                "tip y = %.6f m, time %.3f s\n",
                n, rep.result.converged ? "yes" : "no", rep.result.status.c_str(), rep.result.iterations,
                rep.result.residual, rep.result.stability.c_str(), rep.result.state.q[3 * (n - 1) + 1], seconds);
    return rep.result.converged ? 0 : 1;
}
