// Cost of flexible bodies (issue 40, docs/benchmarks.md "Flexible bodies"):
//  1. an ANCF cable pendulum (pinned at node 0, rho A = 1 kg/m, EA = 1e4 N, EI = 10 N m^2,
//     L = 1 m, released horizontal) meshed into N elements: the median time of one right-hand
//     side of the augmented formulation (a step of an explicit Runge-Kutta pair costs its stages'
//     right-hand sides), with the slope of log(time) against log(N);
//  2. a crank-rocker four-bar (crank 1 m, coupler from (0, 1) to (3, 2), rocker 2 m, ground 3 m)
//     with its coupler rigid and as an ANCF cable of the same mass (E A = 1e6 N, EI = 1e3 N m^2,
//     4 elements): the cost of one rhs and of one second of motion (dopri5 at 1e-6: steps and
//     CPU time), and the flexible to rigid ratios.
// Times are the thread's CPU time (thread_cpu_clock): the machine is shared.
//   bench_flexible [N...]   (default 2 4 8 16 32 64)
#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "augmented_rhs.hpp"
#include "bench_stats.hpp"

namespace {

std::string cable_pendulum(int elements) {
    std::ostringstream s;
    s << "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n"
      << "  - {name: rope, type: ancf_cable, from: [0, 0], to: [1, 0], elements: " << elements
      << ", modulus: 1.0e4, area: 1.0, second_moment: 1.0e-3, density: 1.0}\n"
      << "joints:\n  - {name: pin, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n";
    return s.str();
}

// The crank-rocker with a coupler of rho A = 1 kg/m (length sqrt(10)), rigid or flexible.
std::string four_bar(bool flexible) {
    const double length = std::sqrt(10.0), mass = length;
    std::ostringstream s;
    s.precision(17);
    s << "dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
      << "  - {name: crank, mass: 1, inertia: 0.0833333333333333, position: [0, 0.5], angle: 1.5707963267948966, "
         "angular_velocity: 6}\n"
      << "  - {name: rocker, mass: 2, inertia: 0.6666666666666666, position: [3, 1], angle: 1.5707963267948966}\n";
    if (flexible)
        s << "flexible_bodies:\n  - {name: coupler, type: ancf_cable, from: [0, 1], to: [3, 2], elements: 4, "
             "modulus: 1.0e6, area: 1.0, second_moment: 1.0e-3, density: 1.0}\n";
    else
        s << "  - {name: coupler, mass: " << mass << ", inertia: " << mass * length * length / 12
          << ", position: [1.5, 1.5], angle: " << std::atan2(1.0, 3.0) << "}\n";
    const std::string coupler_start = flexible ? "{body: coupler, node: 0}" : "coupler";
    const std::string coupler_end = flexible ? "{body: coupler, node: 4}" : "coupler";
    s << "joints:\n"
      << "  - {name: A, type: revolute, bodies: [ground, crank], point: [0, 0]}\n"
      << "  - {name: B, type: revolute, bodies: [crank, " << coupler_start << "], point: [0, 1]}\n"
      << "  - {name: C, type: revolute, bodies: [" << coupler_end << ", rocker], point: [3, 2]}\n"
      << "  - {name: D, type: revolute, bodies: [rocker, ground], point: [3, 0]}\n";
    return s.str();
}

double rhs_seconds(mbd::Registry& registry, const mbd::Model& model) {
    mbd::ModelSystem system(model);
    mbd::State state = system.initial_state();
    system.assemble(state, true);
    system.consistent_velocities(state, true);
    return augmented_rhs_seconds(registry, system, state);
}

struct Run {
    double seconds = 0.0;
    long steps = 0, rhs = 0;
};

// One second of motion, augmented + dopri5 at 1e-6, no output but the run's own rows.
Run one_second(mbd::Registry& registry, const mbd::Model& model) {
    mbd::SimulationSettings settings;
    settings.formulation = "augmented";
    settings.integrator = "dopri5";
    settings.integration.tolerance = 1e-6;
    settings.t_end = 1.0;
    settings.output_step = 0.1;
    settings.progress = false;
    settings.messages = mbd::MessageLog::silent();
    const auto start = thread_cpu_clock::now();
    const mbd::SimulationResult result = mbd::simulate(model, registry, settings);
    Run run;
    run.seconds = std::chrono::duration<double>(thread_cpu_clock::now() - start).count();
    run.steps = result.stats.steps;
    run.rhs = result.stats.rhs_evaluations;
    return run;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> meshes = {2, 4, 8, 16, 32, 64};
    if (argc > 1) {
        meshes.clear();
        for (int k = 1; k < argc; ++k) meshes.push_back(std::atoi(argv[k]));
    }
    mbd::Registry registry;
    std::printf("ANCF cable pendulum, augmented rhs\n%9s %13s %10s %16s\n", "elements", "coordinates", "rhs [us]",
                "per element [us]");
    std::vector<double> n, t;
    for (int elements : meshes) {
        const mbd::Model model = mbd::load_scene_text(cable_pendulum(elements), "bench.yaml", registry);
        const double seconds = rhs_seconds(registry, model);
        std::printf("%9d %13d %10.2f %16.3f\n", elements, 4 * (elements + 1), 1e6 * seconds, 1e6 * seconds / elements);
        std::fflush(stdout);
        n.push_back(elements), t.push_back(seconds);
    }
    std::printf("slope of log(rhs time) against log(elements): %.3f\n\n", slope(n, t));

    std::printf("four-bar, coupler rigid against ANCF (4 elements)\n%9s %10s %8s %8s %14s %12s\n", "coupler",
                "rhs [us]", "steps", "rhs", "1 s run [ms]", "per step [us]");
    double rhs[2], run_time[2], per_step[2];
    for (int flexible = 0; flexible < 2; ++flexible) {
        const mbd::Model model = mbd::load_scene_text(four_bar(flexible), "four-bar.yaml", registry);
        rhs[flexible] = rhs_seconds(registry, model);
        const Run run = one_second(registry, model);
        run_time[flexible] = run.seconds;
        per_step[flexible] = run.seconds / static_cast<double>(run.steps);
        std::printf("%9s %10.2f %8ld %8ld %14.2f %12.2f\n", flexible ? "ANCF" : "rigid", 1e6 * rhs[flexible], run.steps,
                    run.rhs, 1e3 * run.seconds, 1e6 * per_step[flexible]);
        std::fflush(stdout);
    }
    std::printf("ratios flexible / rigid: rhs %.2f, per step %.2f, one second of motion %.1f\n", rhs[1] / rhs[0],
                per_step[1] / per_step[0], run_time[1] / run_time[0]);
    return 0;
}
