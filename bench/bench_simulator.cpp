// The stepping Simulator (docs/embedding.md) against a whole run, and the cost of a user
// force callback (issue 38; docs/benchmarks.md, "Stepping"). On one scene (default the
// 5-link chain) and one integrator, the median CPU time of:
//   simulate  simulate(): the whole run as `mbd simulate` makes it, its rows at the default
//             output step t_end / 1000 (computed, not written)
//   whole   one advance_to(t_end)
//   pieces  advance_to in `pieces` calls to t_end
//   force   one advance_to(t_end) with a user force that returns zeros (the callback's cost)
// and their ratios; the callback's overhead per call is (force - whole) / right-hand sides, and
// an advance_to call's (pieces - whole) / pieces. CPU time of the calling thread (the runs are
// interleaved, round by round, so that a load on the machine falls on all three alike).
//   bench_simulator [scene=scenes/bench/chain-5.yaml] [integrator=dopri5] [t_end=2] [pieces=1000]
#include <mbd/app/scene_sections.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>
#include <mbd/simulator.hpp>

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

double thread_seconds() {
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

struct Run {
    double seconds = 0.0;
    long steps = 0, rhs = 0;
};

Run timed(const mbd::Model& model, mbd::Registry& registry, const mbd::SimulationSettings& settings, int pieces,
          bool user_force) {
    mbd::Simulator sim(model, registry, settings);
    if (user_force) {
        const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv());
        sim.set_user_force([&zero](const mbd::State&) { return zero; });
    }
    const double start = thread_seconds();
    for (int k = 1; k <= pieces; ++k) sim.advance_to(k == pieces ? settings.t_end : settings.t_end * k / pieces);
    return {thread_seconds() - start, sim.stats().steps, sim.stats().rhs_evaluations};
}

Run timed_simulate(const mbd::Model& model, mbd::Registry& registry, const mbd::SimulationSettings& settings) {
    const double start = thread_seconds();
    const mbd::SimulationResult result = mbd::simulate(model, registry, settings);
    return {thread_seconds() - start, result.stats.steps, result.stats.rhs_evaluations};
}

Run median(std::vector<Run> runs) {
    std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.seconds < b.seconds; });
    return runs[runs.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    mbd::declare_application_scene_sections();  // scenes/bench keep their `bench:`
    const std::string path = argc > 1 ? argv[1] : "scenes/bench/chain-5.yaml";
    mbd::SimulationSettings settings;
    settings.integrator = argc > 2 ? argv[2] : "dopri5";
    settings.t_end = argc > 3 ? std::atof(argv[3]) : 2.0;
    const int pieces = argc > 4 ? std::atoi(argv[4]) : 1000;
    if (settings.integrator == "rk4" || settings.integrator == "euler" || settings.integrator == "generalized_alpha")
        settings.integration.step = 1e-3;
    settings.messages = mbd::MessageLog::silent();
    mbd::Registry registry;
    const mbd::Model model = mbd::load_scene(path, registry);
    settings.progress = false;
    std::vector<Run> simulates, wholes, cuts, forces;
    for (int round = 0; round < 7; ++round) {
        simulates.push_back(timed_simulate(model, registry, settings));
        wholes.push_back(timed(model, registry, settings, 1, false));
        cuts.push_back(timed(model, registry, settings, pieces, false));
        forces.push_back(timed(model, registry, settings, 1, true));
    }
    const Run simulated = median(simulates), whole = median(wholes), cut = median(cuts), force = median(forces);
    std::printf("scene %s, %s, t_end %g\n", path.c_str(), settings.integrator.c_str(), settings.t_end);
    std::printf("simulate()       %9.3f ms  %6ld steps %7ld rhs  (rows every t_end / 1000)\n", 1e3 * simulated.seconds,
                simulated.steps, simulated.rhs);
    std::printf("whole run        %9.3f ms  %6ld steps %7ld rhs\n", 1e3 * whole.seconds, whole.steps, whole.rhs);
    std::printf("%4d advance_to  %9.3f ms  %6ld steps %7ld rhs  ratio %.3f (to simulate() %.3f)  overhead %.3f us per call\n",
                pieces, 1e3 * cut.seconds, cut.steps, cut.rhs, cut.seconds / whole.seconds,
                cut.seconds / simulated.seconds, 1e6 * (cut.seconds - whole.seconds) / pieces);
    std::printf("user force       %9.3f ms  %6ld steps %7ld rhs  ratio %.3f  overhead %.3f us per call, %.3f us per step\n",
                1e3 * force.seconds, force.steps, force.rhs, force.seconds / whole.seconds,
                1e6 * (force.seconds - whole.seconds) / static_cast<double>(force.rhs),
                1e6 * (force.seconds - whole.seconds) / static_cast<double>(force.steps));
    return 0;
}
