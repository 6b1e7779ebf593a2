// Embedding the mbd engine (docs/embedding.md): load a scene shipped with mbd, simulate it,
// and compute a number from the samples as they come. Here the pendulum of IFToMM benchmark
// A01 (scenes/dynamics/pendulum-a01.yaml), released at rest from the horizontal: the period,
// from the times its angular velocity passes through zero (the turning points, half a period
// apart), and the largest drift of its energy T + V from the start.
//
// Usage: pendulum_period [SCENE] [BODY]   (default: the installed pendulum-a01.yaml, bob)
#include <mbd/engine.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

int column_of(const std::vector<std::string>& columns, const std::string& name) {
    const auto found = std::find(columns.begin(), columns.end(), name);
    if (found == columns.end()) throw std::runtime_error("the result has no column " + name);
    return static_cast<int>(found - columns.begin());
}

}  // namespace

int main(int argc, char** argv) {
    const std::string scene = argc > 1 ? argv[1] : std::string(MBD_SCENES_DIR) + "/dynamics/pendulum-a01.yaml";
    const std::string body = argc > 2 ? argv[2] : "bob";
    try {
        mbd::Registry registry;  // the plugins installed beside libmbd_core, then MBD_PLUGIN_PATH
        const mbd::Model model = mbd::load_scene(scene, registry);

        mbd::SimulationSettings settings;
        settings.integrator = "dop853";
        settings.integration.tolerance = 1e-11;
        settings.t_end = 5.0;
        settings.output_step = 1e-3;
        settings.diagnostics = true;  // adds kinetic_energy and potential_energy to each row
        settings.progress = false;
        settings.messages = mbd::MessageLog::silent();

        std::vector<std::string> columns = mbd::motion_columns(model);
        for (const std::string& c : mbd::diagnostic_columns()) columns.push_back(c);
        const int omega = column_of(columns, body + ".omega");
        const int kinetic = column_of(columns, "kinetic_energy"), potential = column_of(columns, "potential_energy");

        std::vector<double> turning_times;  // omega through zero, linearly interpolated
        double previous_t = 0.0, previous_omega = 0.0, energy0 = 0.0, drift = 0.0;
        bool first = true;
        const mbd::SimulationResult run = mbd::simulate(model, registry, settings, [&](const mbd::SimulationSample& s) {
            const std::vector<double>& row = *s.row;
            const double energy = row[kinetic] + row[potential];
            if (first) energy0 = energy;
            drift = std::max(drift, std::abs(energy - energy0));
            // a sign change after the release (at rest: omega = 0 exactly at t = 0)
            if (!first && previous_omega != 0.0 && (previous_omega < 0.0) != (row[omega] < 0.0))
                turning_times.push_back(previous_t + (s.state.t - previous_t) * previous_omega / (previous_omega - row[omega]));
            previous_t = s.state.t;
            previous_omega = row[omega];
            first = false;
            return true;
        });
        if (turning_times.size() < 2) throw std::runtime_error("fewer than two turning points in the run");
        // from the release (a turning point at t = 0) to the second turning point: one period
        std::printf("mbd engine %s, scene %s\n", mbd::engine_version(), model.name.c_str());
        std::printf("integrator %s, %ld rows, %ld steps\n", run.integrator.c_str(), run.rows, run.stats.steps);
        std::printf("period_s %.12f\n", turning_times[1]);
        std::printf("half_period_s %.12f\n", turning_times[0]);
        std::printf("energy_drift_J %.3e\n", drift);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pendulum_period: error: %s\n", e.what());
        return 2;
    }
}
