#include "support/test_support.hpp"


#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace mbd::test {

std::filesystem::path source_dir() { return MBD_SOURCE_DIR; }
std::filesystem::path build_plugin_dir() { return std::filesystem::path(MBD_BUILD_DIR) / "lib/mbd/plugins"; }
std::filesystem::path scene_path(const std::string& relative) { return source_dir() / "scenes" / relative; }

Registry& shared_registry() {
    static Registry registry({build_plugin_dir()});
    return registry;
}

namespace {
std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}
}  // namespace

std::filesystem::path write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string read_text(const std::filesystem::path& path) {
    EXPECT_TRUE(std::filesystem::is_regular_file(path)) << path;
    return slurp(path);
}

SimulationSettings adaptive_run(const std::string& formulation, const std::string& integrator, double tolerance,
                                double t_end, double output_step) {
    SimulationSettings s;
    s.formulation = formulation;
    s.integrator = integrator;
    s.integration.tolerance = tolerance;
    s.t_end = t_end;
    s.output_step = output_step;
    s.progress = false;
    s.messages = MessageLog::silent();
    return s;
}

CommandResult run_command(const std::string& command) {
    const auto dir = std::filesystem::temp_directory_path();
    const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(std::rand());
    const auto out = dir / ("mbd_test_out_" + tag);
    const auto err = dir / ("mbd_test_err_" + tag);
    const std::string full = command + " >" + out.string() + " 2>" + err.string() + " </dev/null";
    const int status = std::system(full.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
}

CommandResult run_mbd(const std::string& arguments) {
    return run_command(std::string("env -u MBD_PLUGIN_PATH ") + MBD_EXECUTABLE + " " + arguments);
}

Model load(const std::string& relative) { return load_scene(scene_path(relative).string(), shared_registry()); }

Model scene(const std::string& yaml, const std::string& label) { return load_scene_text(yaml, label, shared_registry()); }

std::shared_ptr<Formulation> make_formulation(const std::string& type, Param& node,
                                              const std::vector<std::pair<std::string, std::string>>& keys) {
    node = Param();
    node.kind = Param::Kind::Map;
    for (const auto& [key, value] : keys) {
        Param p;
        p.kind = Param::Kind::Scalar;
        p.text = value;
        node.fields[key] = p;
    }
    FormulationSpec spec{type, type, Params("formulation '" + type + "'", &node)};
    return shared_registry().create_formulation(spec, "test");
}

State random_consistent_state(System& system, std::mt19937& rng, double spread) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    State s = system.initial_state();
    s.t = 0.0;
    system.assemble(s, true);
    Eigen::VectorXd dv(system.nv());
    for (int k = 0; k < dv.size(); ++k) dv[k] = spread * u(rng);
    system.advance_positions(s.q, dv);
    system.assemble(s, true);
    for (int k = 0; k < s.v.size(); ++k) s.v[k] = 3.0 * u(rng);
    system.consistent_velocities(s, true);
    return s;
}

std::filesystem::path scratch(const std::string& name) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("mbd_test_" + std::to_string(::getpid()) + "_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

int Csv::column(const std::string& name) const {
    for (size_t k = 0; k < header.size(); ++k)
        if (header[k] == name) return static_cast<int>(k);
    return -1;
}

Csv read_csv(const std::filesystem::path& path) {
    auto split = [](const std::string& line) {
        std::vector<std::string> out;
        std::stringstream s(line);
        std::string item;
        while (std::getline(s, item, ',')) out.push_back(item);
        return out;
    };
    Csv csv;
    std::ifstream in(path);
    std::string line;
    EXPECT_TRUE(std::getline(in, line)) << path;
    csv.header = split(line);
    while (std::getline(in, line)) {
        const auto cells = split(line);
        EXPECT_EQ(cells.size(), csv.header.size()) << "incomplete row: " << line;
        std::vector<double> row;
        for (const auto& c : cells) {
            size_t used = 0;
            const double x = std::stod(c, &used);
            EXPECT_EQ(used, c.size()) << c;
            EXPECT_TRUE(std::isfinite(x)) << c;
            row.push_back(x);
        }
        csv.rows.push_back(row);
    }
    return csv;
}

double position_difference(const Model& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    if (model.dimension == Dimension::Planar) return (a - b).lpNorm<Eigen::Infinity>();
    double worst = 0.0;
    for (int body = 0; body < model.body_count(); ++body) {
        const int o = 7 * body;
        worst = std::max(worst, (a.segment<3>(o) - b.segment<3>(o)).lpNorm<Eigen::Infinity>());
        const Eigen::Vector4d pa = a.segment<4>(o + 3), pb = b.segment<4>(o + 3);
        worst = std::max(worst, std::min((pa - pb).lpNorm<Eigen::Infinity>(), (pa + pb).lpNorm<Eigen::Infinity>()));
    }
    return worst;
}

std::string g17(double x) {
    std::ostringstream o;
    o.precision(17);
    o << x;
    return o.str();
}

Eigen::Vector2d a01_bob_position(double t) {
    const double m = 1.0, l = 1.0, g = 9.81, J = 1.0e-6, theta0 = M_PI / 2;
    const double k = std::sin(theta0 / 2);
    const double K = boost::math::ellint_1(k);
    const double w = std::sqrt(m * g * l / (J + m * l * l));
    const double theta = 2.0 * std::asin(k * boost::math::jacobi_sn(k, K - w * t));
    return Eigen::Vector2d(l * std::sin(theta), -l * std::cos(theta));
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "'" << from << "' is not in the text";
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace mbd::test
