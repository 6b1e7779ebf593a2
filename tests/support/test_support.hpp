// Shared helpers for the test programs: the build tree's plugin registry, scene paths,
// formulations and states, scratch folders and CSV output, and running the mbd command.
#pragma once

#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/kit/system.hpp>
#include <mbd/simulation.hpp>

#include "support/test_paths.hpp"

#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace mbd::test {

std::filesystem::path source_dir();
std::filesystem::path build_plugin_dir();
std::filesystem::path scene_path(const std::string& relative);  // under scenes/

// A registry over the build tree's plugins only (MBD_PLUGIN_PATH ignored).
Registry& shared_registry();

// A scene under scenes/, and a scene from YAML text (label: its file name in messages).
Model load(const std::string& relative);
Model scene(const std::string& yaml, const std::string& label = "test.yaml");
// A formulation plugin with the options in `node` (reset to a map of `keys`; it must outlive the result).
std::shared_ptr<Formulation> make_formulation(const std::string& type, Param& node,
                                              const std::vector<std::pair<std::string, std::string>>& keys = {});
// A random consistent state near the scene's initial configuration: random coordinate
// increments of size `spread`, assembled; random velocities, made consistent.
State random_consistent_state(System& system, std::mt19937& rng, double spread);

// The whole text of a file.
std::string read_text(const std::filesystem::path& path);
// Writes `text` as the whole file (bytes as given); returns the path.
std::filesystem::path write_text(const std::filesystem::path& path, const std::string& text);

// A quiet adaptive run to t_end, sampled every output_step: no progress bar, no formulation
// messages; the caller adds reactions, diagnostics or an output file.
SimulationSettings adaptive_run(const std::string& formulation, const std::string& integrator, double tolerance,
                                double t_end, double output_step);
// A fresh, empty scratch folder for this test process.
std::filesystem::path scratch(const std::string& name);
// A CSV written by mbd: header and numeric rows (a cell that is not a finite number, or a row
// of the wrong length, is a test failure).
struct Csv {
    std::vector<std::string> header;
    std::vector<std::vector<double>> rows;
    int column(const std::string& name) const;  // -1 when absent
};
Csv read_csv(const std::filesystem::path& path);
// Largest coordinate difference of two q vectors; for spatial bodies the Euler parameters p and
// -p are the same orientation, so the nearer sign is compared.
double position_difference(const Model& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b);
// IFToMM A01 as the compound pendulum of scenes/dynamics/pendulum-a01.yaml (bob 1 kg with
// centroidal inertia 1e-6 kg m^2 on a 1 m link, g = 9.81, released at rest from the
// horizontal): the bob position at t from the closed form theta(t) = 2 asin(k sn(K - w t, k)),
// k = sin(theta0 / 2), w^2 = m g l / J_O (reference/README.md).
Eigen::Vector2d a01_bob_position(double t);
// All 17 significant digits, for numbers written into scene text.
std::string g17(double x);

// `text` with its first `from` replaced by `to` (a bad-input variant of a good scene); a test
// failure when `from` is not in it.
std::string replaced(std::string text, const std::string& from, const std::string& to);

struct CommandResult {
    int exit_code = -1;
    std::string out;
    std::string err;
};
// Run the mbd executable with the given argument string (shell-quoted by the caller).
CommandResult run_mbd(const std::string& arguments);
// Run any shell command, capturing stdout and stderr.
CommandResult run_command(const std::string& command);

}  // namespace mbd::test
