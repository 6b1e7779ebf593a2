// Work-precision benchmarks (see bench.hpp).
#include <mbd/bench.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/progress_bar.hpp>

#include <mbd/scene.hpp>
#include <mbd/sdk/number.hpp>
#include <mbd/sdk/rotation.hpp>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <yaml-cpp/yaml.h>

#include "scene_source.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace mbd {

namespace {

std::string num(double x) {
    if (!std::isfinite(x)) return "nan";
    char b[40];
    std::snprintf(b, sizeof b, "%.6g", x);
    return b;
}

std::string where(const std::string& file, const YAML::Node& n) {
    return file + ":" + std::to_string(n.Mark().line + 1);
}

double as_double(const std::string& file, const YAML::Node& n, const std::string& what) {
    if (!n.IsScalar()) throw InputError(where(file, n), "bench: '" + what + "' must be a number");
    double value = 0.0;
    const NumberText read = parse_number(n.Scalar(), value);
    if (read != NumberText::Valid) throw InputError(where(file, n), "bench: " + number_problem(read, what, n.Scalar()));
    return value;
}

std::vector<double> as_list(const std::string& file, const YAML::Node& n, const std::string& what) {
    std::vector<double> out;
    if (!n) return out;
    if (!n.IsSequence()) throw InputError(where(file, n), "bench: '" + what + "' must be a list of numbers");
    for (const auto& item : n) out.push_back(as_double(file, item, what));
    return out;
}

void check_keys(const std::string& file, const YAML::Node& n, const std::string& what,
                const std::vector<std::string>& accepted) {
    if (!n.IsMap()) throw InputError(where(file, n), "bench: '" + what + "' must be a map of keys");
    for (const auto& kv : n) {
        const std::string key = kv.first.as<std::string>();
        if (std::find(accepted.begin(), accepted.end(), key) == accepted.end()) {
            std::string list;
            for (const auto& a : accepted) list += (list.empty() ? "'" : ", '") + a + "'";
            throw InputError(where(file, kv.first),
                             "bench: unknown key '" + key + "' in '" + what + "'; accepted keys are " + list);
        }
    }
}

double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Position of a point u (body frame) of body b in state q.
Eigen::Vector3d point_position(const Model& model, const Eigen::VectorXd& q, int b, const Eigen::Vector3d& u) {
    const int o = model.q_offset(b);
    if (model.dimension == Dimension::Planar) {
        const double c = std::cos(q[o + 2]), s = std::sin(q[o + 2]);
        return Eigen::Vector3d(q[o] + c * u.x() - s * u.y(), q[o + 1] + s * u.x() + c * u.y(), 0.0);
    }
    const Vec4 p = q.segment<4>(o + 3);
    return q.segment<3>(o) + rotation_from_euler_parameters(p.normalized()) * u;
}

std::vector<int> measured_bodies(const Model& model, const BenchMeasure& m) {
    std::vector<int> out;
    for (const auto& name : m.bodies) {
        const int b = model.body_index(name);
        if (b < 0) throw InputError(model.source, "bench: measured body '" + name + "' is not a body of the scene");
        out.push_back(b);
    }
    return out;
}

// ---- progress over a scene's grid (progress_bar.hpp); a stop signal ends the grid here
class GridProgress {
public:
    GridProgress(bool enabled, std::string label, int total)
        : bar_(enabled && total > 0), label_(std::move(label)), total_(total) {}
    void update(int done, const std::string& what) {
        stop_if_interrupted();
        bar_.update(static_cast<double>(done) / total_,
                    label_ + " " + std::to_string(done) + "/" + std::to_string(total_) + " " + what);
    }
    void finish() { bar_.finish(); }

private:
    ProgressBar bar_;
    std::string label_;
    int total_;
};

// ---- closed forms
// The parallelogram N four-bar (A02) in its 1-DOF mode: n_c cranks (rods of length L,
// mass m, pinned to the ground at their ends, all at the same angle theta from +x) and n_k
// couplers (rods translating with the crank tips): (n_c m L^2 / 3 + n_k m L^2) theta'' =
// -(n_c m g L / 2 + n_k m g L) cos(theta). Integrated by classical RK4 with 2e-5 s steps
// (truncation error ~1e-16 per unit time at these rates); returns the tip of crank 0.
Eigen::MatrixXd four_bar_closed_form(const std::map<std::string, double>& p, const std::vector<double>& times) {
    auto get = [&](const char* k, double d) {
        auto it = p.find(k);
        return it == p.end() ? d : it->second;
    };
    const double nc = get("cranks", 3), nk = get("couplers", 2), L = get("length", 1), m = get("mass", 1),
                 g = get("g", 9.81);
    double th = get("theta0", M_PI / 2), om = get("omega0", -1.0);
    const double I = nc * m * L * L / 3.0 + nk * m * L * L, W = nc * m * g * L / 2.0 + nk * m * g * L;
    auto f = [&](double theta) { return -W / I * std::cos(theta); };
    Eigen::MatrixXd out(times.size(), 3);
    double t = 0.0;
    const double h_max = 2e-5;
    for (size_t k = 0; k < times.size(); ++k) {
        while (t < times[k] - 1e-14) {
            const double h = std::min(h_max, times[k] - t);
            const double k1t = om, k1o = f(th);
            const double k2t = om + 0.5 * h * k1o, k2o = f(th + 0.5 * h * k1t);
            const double k3t = om + 0.5 * h * k2o, k3o = f(th + 0.5 * h * k2t);
            const double k4t = om + h * k3o, k4o = f(th + h * k3t);
            th += h / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t);
            om += h / 6.0 * (k1o + 2 * k2o + 2 * k3o + k4o);
            t += h;
        }
        out.row(k) << L * std::cos(th), L * std::sin(th), 0.0;
    }
    return out;
}

// Steady precession (heavy top / gyroscope): the measured point turns about `axis`
// (through the origin) at `rate`: r(t) = Rot(axis, rate t) r(0).
Eigen::MatrixXd precession_closed_form(const Model& model, const BenchMeasure& measure,
                                       const std::map<std::string, double>& p, const std::vector<double>& times) {
    auto get = [&](const char* k, double d) {
        auto it = p.find(k);
        return it == p.end() ? d : it->second;
    };
    const double rate = get("rate", 0.0);
    const Eigen::Vector3d axis = Eigen::Vector3d(get("axis_x", 0), get("axis_y", 0), get("axis_z", 1)).normalized();
    const std::vector<int> bodies = measured_bodies(model, measure);
    const Eigen::VectorXd q0 = model.initial_state().q;
    Eigen::MatrixXd out(times.size(), 3 * bodies.size());
    for (size_t i = 0; i < bodies.size(); ++i) {
        const Eigen::Vector3d r0 = point_position(model, q0, bodies[i], measure.points[i]);
        for (size_t k = 0; k < times.size(); ++k)
            out.block<1, 3>(k, 3 * i) = (Eigen::AngleAxisd(rate * times[k], axis) * r0).transpose();
    }
    return out;
}

// Test Set car axis at t = 3 (Mazzia & Magherini; /work/shared/reference/README.md).
Trajectory car_axis_published() {
    Trajectory t;
    t.times = {3.0};
    t.points.resize(1, 6);
    t.points << 4.934557842755629e-2, 4.969894602303324e-1, 0.0, 1.041742524885400, 3.739110272652214e-1, 0.0;
    return t;
}

// ---- peers: bench/peers/mbd_peer_<engine> MODEL T_END OUTPUT_STEP tol|step VALUE
// prints "cpu_s steps" then one line per output time "t x1 y1 z1 [x2 y2 z2 ...]".
struct PeerRun {
    bool ok = false;
    std::string message;
    double cpu_s = 0.0;
    long steps = 0;
    Trajectory trajectory;
};

PeerRun run_peer(const std::string& exe, const std::string& model, double t_end, double output_step, bool tolerance,
                 double value, int points) {
    PeerRun r;
    const std::string cmd = "'" + exe + "' " + model + " " + num(t_end) + " " + num(output_step) + " " +
                            (tolerance ? "tol " : "step ") + num(value) + " 2>&1";
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) {
        r.message = "could not start " + exe;
        return r;
    }
    std::string text;
    char buffer[4096];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) text.append(buffer, n);
    const int status = ::pclose(pipe);
    std::istringstream in(text);
    std::string first;
    std::getline(in, first);
    std::istringstream head(first);
    if (status != 0 || !(head >> r.cpu_s >> r.steps)) {
        r.message = text.substr(0, 200);
        while (!r.message.empty() && (r.message.back() == '\n' || r.message.back() == '\r')) r.message.pop_back();
        if (r.message.empty()) r.message = "exit status " + std::to_string(status);
        return r;
    }
    std::vector<std::vector<double>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::vector<double> row;
        double x;
        while (ls >> x) row.push_back(x);
        if (static_cast<int>(row.size()) == 1 + 3 * points) rows.push_back(row);
    }
    r.trajectory.points.resize(rows.size(), 3 * points);
    for (size_t k = 0; k < rows.size(); ++k) {
        r.trajectory.times.push_back(rows[k][0]);
        for (int c = 0; c < 3 * points; ++c) r.trajectory.points(k, c) = rows[k][1 + c];
    }
    r.ok = true;
    return r;
}

std::string json_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (c == '\n') {
            out += "\\n";
        } else if (static_cast<unsigned char>(c) < 0x20) {
            out += ' ';
        } else {
            out += c;
        }
    }
    return out;
}

std::string json_number(double x) {
    if (!std::isfinite(x)) return "null";
    char b[40];
    std::snprintf(b, sizeof b, "%.9g", x);
    return b;
}

std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
    return out + "\"";
}

}  // namespace

std::string BenchMeasure::describe() const {
    std::string who;
    for (size_t i = 0; i < bodies.size(); ++i) {
        who += (i ? ", " : "") + bodies[i];
        if (!points[i].isZero()) who += " point (" + num(points[i].x()) + ", " + num(points[i].y()) + ", " +
                                        num(points[i].z()) + ")";
    }
    return (norm == "final" ? "final |r - r_ref| of " : "max |r - r_ref| over the output times of ") + who;
}

BenchSpec load_bench_spec(const std::string& file) {
    // the file's own 'bench:' key (not inherited through 'base:'), read within the scene limits
    const YAML::Node root = detail::SceneTreeReader().parse(detail::read_scene_file(file), file);
    BenchSpec spec;
    spec.scene = file;
    spec.name = root["name"] ? root["name"].as<std::string>() : std::filesystem::path(file).stem().string();
    const YAML::Node b = root["bench"];
    if (!b) throw InputError(file, "the scene has no 'bench:' key (docs/scene-format.md, Benchmarks)");
    check_keys(file, b, "bench", {"t_end", "output_step", "measure", "reference", "runs", "peers"});
    if (!b["t_end"]) throw InputError(where(file, b), "bench: missing key 't_end'");
    spec.t_end = as_double(file, b["t_end"], "t_end");
    if (b["output_step"]) spec.output_step = as_double(file, b["output_step"], "output_step");
    if (!(spec.t_end > 0)) throw InputError(where(file, b["t_end"]), "bench: 't_end' must be positive");

    const YAML::Node m = b["measure"];
    if (!m) throw InputError(where(file, b), "bench: missing key 'measure' ({body: NAME, quantity: position, norm: max})");
    check_keys(file, m, "measure", {"body", "bodies", "point", "points", "quantity", "norm"});
    if (m["body"]) spec.measure.bodies.push_back(m["body"].as<std::string>());
    if (m["bodies"])
        for (const auto& x : m["bodies"]) spec.measure.bodies.push_back(x.as<std::string>());
    if (spec.measure.bodies.empty()) throw InputError(where(file, m), "bench: 'measure' needs 'body' or 'bodies'");
    spec.measure.points.assign(spec.measure.bodies.size(), Eigen::Vector3d::Zero());
    auto read_point = [&](const YAML::Node& n) {
        const std::vector<double> v = as_list(file, n, "point");
        if (v.size() < 2 || v.size() > 3) throw InputError(where(file, n), "bench: a point is [x, y] or [x, y, z]");
        return Eigen::Vector3d(v[0], v[1], v.size() == 3 ? v[2] : 0.0);
    };
    if (m["point"]) spec.measure.points[0] = read_point(m["point"]);
    if (m["points"]) {
        if (m["points"].size() != spec.measure.bodies.size())
            throw InputError(where(file, m["points"]), "bench: 'points' needs one point per measured body");
        for (size_t i = 0; i < spec.measure.bodies.size(); ++i) spec.measure.points[i] = read_point(m["points"][i]);
    }
    if (m["quantity"]) spec.measure.quantity = m["quantity"].as<std::string>();
    if (spec.measure.quantity != "position")
        throw InputError(where(file, m["quantity"]), "bench: only 'quantity: position' is measured");
    if (m["norm"]) spec.measure.norm = m["norm"].as<std::string>();
    if (spec.measure.norm != "max" && spec.measure.norm != "final")
        throw InputError(where(file, m["norm"]), "bench: 'norm' is max or final");

    const YAML::Node r = b["reference"];
    if (!r) throw InputError(where(file, b), "bench: missing key 'reference' ({kind: closed_form|published|tight_run, ...})");
    if (!r.IsMap()) throw InputError(where(file, r), "bench: 'reference' must be a map of keys");
    spec.reference.kind = r["kind"] ? r["kind"].as<std::string>() : "";
    for (const auto& kv : r) {
        const std::string key = kv.first.as<std::string>();
        if (key == "kind") continue;
        if (key == "name") spec.reference.name = kv.second.as<std::string>();
        else if (key == "formulation") spec.reference.formulation = kv.second.as<std::string>();
        else if (key == "integrator") spec.reference.integrator = kv.second.as<std::string>();
        else if (key == "cross_check") spec.reference.cross_check = kv.second.as<std::string>();
        else if (key == "tolerance") spec.reference.tolerance = as_double(file, kv.second, key);
        else spec.reference.params[key] = as_double(file, kv.second, key);
    }
    if (spec.reference.kind != "closed_form" && spec.reference.kind != "published" && spec.reference.kind != "tight_run")
        throw InputError(where(file, r), "bench: reference 'kind' is closed_form, published or tight_run");

    const YAML::Node runs = b["runs"];
    if (!runs || !runs.IsSequence()) throw InputError(where(file, b), "bench: 'runs' must be a list of series");
    for (const auto& s : runs) {
        check_keys(file, s, "runs", {"formulation", "integrator", "tolerances", "steps"});
        BenchSeries series;
        series.formulation = s["formulation"] ? s["formulation"].as<std::string>() : "augmented";
        series.integrator = s["integrator"] ? s["integrator"].as<std::string>() : "dopri5";
        series.tolerances = as_list(file, s["tolerances"], "tolerances");
        series.steps = as_list(file, s["steps"], "steps");
        spec.runs.push_back(series);
    }
    if (const YAML::Node p = b["peers"]) {
        check_keys(file, p, "peers", {"model", "simbody", "mujoco"});
        if (p["model"]) spec.peer_model = p["model"].as<std::string>();
        for (const char* engine : {"simbody", "mujoco"}) {
            if (!p[engine]) continue;
            const YAML::Node e = p[engine];
            std::vector<YAML::Node> list;
            if (e.IsSequence())
                for (const auto& x : e) list.push_back(x);
            else
                list.push_back(e);
            for (const auto& s : list) {
                check_keys(file, s, std::string("peers.") + engine, {"integrator", "tolerances", "steps"});
                BenchPeerSeries ps;
                ps.engine = engine;
                ps.integrator = s["integrator"] ? s["integrator"].as<std::string>() : "default";
                ps.tolerances = as_list(file, s["tolerances"], "tolerances");
                ps.steps = as_list(file, s["steps"], "steps");
                spec.peers.push_back(ps);
            }
        }
    }
    return spec;
}

std::vector<double> bench_output_times(const BenchSpec& spec) {
    const double h = spec.output_step > 0 ? spec.output_step : spec.t_end / 100.0;
    const long n = std::max(1L, static_cast<long>(std::llround(spec.t_end / h)));
    std::vector<double> times;
    for (long k = 1; k < n; ++k) times.push_back(k * h);
    times.push_back(spec.t_end);
    return times;
}

Eigen::MatrixXd pendulum_closed_form(const Model& model, const std::string& body, const std::vector<double>& times) {
    const int b = model.body_index(body);
    if (b < 0) throw InputError(model.source, "pendulum closed form: no body '" + body + "'");
    const Body& B = model.bodies[b];
    const double l = B.position.head<2>().norm();
    const double g = model.gravity.norm();
    const double J_O = B.inertia(2, 2) + B.mass * l * l;
    const double w = std::sqrt(B.mass * g * l / J_O);
    // angle from the downward vertical (gravity along -y): x = l sin(theta), y = -l cos(theta)
    const double theta0 = std::atan2(B.position.x(), -B.position.y());
    const double k = std::sin(std::abs(theta0) / 2.0);
    const double K = boost::math::ellint_1(k);
    const double sign = theta0 >= 0 ? 1.0 : -1.0;
    Eigen::MatrixXd out(times.size(), 3);
    for (size_t i = 0; i < times.size(); ++i) {
        const double sn = boost::math::jacobi_sn(k, K - w * times[i]);
        const double theta = sign * 2.0 * std::asin(std::clamp(k * sn, -1.0, 1.0));
        out.row(i) << l * std::sin(theta), -l * std::cos(theta), 0.0;
    }
    return out;
}

Trajectory sample_trajectory(const Model& model, Registry& registry, const SimulationSettings& settings,
                             const BenchMeasure& measure, SimulationResult& result) {
    const std::vector<int> bodies = measured_bodies(model, measure);
    std::vector<double> times;
    std::vector<Eigen::RowVectorXd> rows;
    result = simulate(model, registry, settings, [&](const SimulationSample& s) {
        if (s.state.t <= 0.0) return true;  // the initial state is not an output time of the bench
        Eigen::RowVectorXd row(3 * bodies.size());
        for (size_t i = 0; i < bodies.size(); ++i)
            row.segment<3>(3 * i) = point_position(model, s.state.q, bodies[i], measure.points[i]).transpose();
        times.push_back(s.state.t);
        rows.push_back(row);
        return true;
    });
    Trajectory t;
    t.times = times;
    t.points.resize(rows.size(), 3 * bodies.size());
    for (size_t k = 0; k < rows.size(); ++k) t.points.row(k) = rows[k];
    return t;
}

double bench_error(const Trajectory& run, const Trajectory& reference, const BenchMeasure& measure) {
    const int points = static_cast<int>(reference.points.cols() / 3);
    if (run.points.cols() != reference.points.cols())
        throw std::invalid_argument("bench_error: the run and the reference measure different points");
    double worst = 0.0, last = 0.0;
    size_t j = 0;
    for (size_t k = 0; k < reference.times.size(); ++k) {
        const double t = reference.times[k];
        const double tol = 1e-9 * std::max(1.0, std::abs(t));
        while (j < run.times.size() && run.times[j] < t - tol) ++j;
        if (j >= run.times.size() || std::abs(run.times[j] - t) > tol)
            throw std::invalid_argument("bench_error: the run has no sample at t = " + num(t));
        double e = 0.0;
        for (int p = 0; p < points; ++p)
            e = std::max(e, (run.points.block<1, 3>(j, 3 * p) - reference.points.block<1, 3>(k, 3 * p)).norm());
        if (!std::isfinite(e)) return std::numeric_limits<double>::quiet_NaN();
        worst = std::max(worst, e);
        last = e;
    }
    return measure.norm == "final" ? last : worst;
}

BenchReferenceData make_bench_reference(const Model& model, Registry& registry, const BenchSpec& spec) {
    BenchReferenceData ref;
    ref.kind = spec.reference.kind;
    const std::vector<double> times = bench_output_times(spec);
    const std::string& name = spec.reference.name;
    if (ref.kind == "closed_form") {
        ref.trajectory.times = times;
        if (name == "pendulum_a01") {
            ref.trajectory.points = pendulum_closed_form(model, spec.measure.bodies.at(0), times);
            ref.description = "closed form pendulum_a01: theta = 2 asin(k sn(K - w t, k)) (Boost.Math)";
        } else if (name == "parallelogram_four_bar") {
            ref.trajectory.points = four_bar_closed_form(spec.reference.params, times);
            ref.description = "closed form parallelogram_four_bar: the 1-DOF parallelogram motion, RK4 at 2e-5 s";
        } else if (name == "steady_precession") {
            ref.trajectory.points = precession_closed_form(model, spec.measure, spec.reference.params, times);
            ref.description = "closed form steady_precession: uniform rotation about the vertical";
        } else {
            throw InputError(spec.scene, "bench: unknown closed form '" + name +
                                             "' (known: pendulum_a01, parallelogram_four_bar, steady_precession)");
        }
    } else if (ref.kind == "published") {
        if (name != "car_axis_t3")
            throw InputError(spec.scene, "bench: unknown published reference '" + name + "' (known: car_axis_t3)");
        ref.trajectory = car_axis_published();
        ref.description = "published: Test Set car axis, (x_l, y_l, x_r, y_r) at t = 3";
    } else {
        SimulationSettings s;
        s.formulation = spec.reference.formulation;
        s.integrator = spec.reference.integrator;
        s.integration.tolerance = spec.reference.tolerance;
        s.t_end = spec.t_end;
        s.output_step = times.front();
        s.progress = false;
        SimulationResult r;
        ref.trajectory = sample_trajectory(model, registry, s, spec.measure, r);
        ref.description = "tight run: " + s.formulation + " + " + s.integrator + " at tol " +
                          num(spec.reference.tolerance);
        if (!spec.reference.cross_check.empty() && spec.reference.cross_check != "none") {
            SimulationSettings c = s;
            c.formulation = spec.reference.cross_check;
            try {
                const Trajectory other = sample_trajectory(model, registry, c, spec.measure, r);
                ref.cross_check = bench_error(other, ref.trajectory, BenchMeasure{spec.measure.bodies,
                                                                                  spec.measure.points, "position", "max"});
                ref.description += ", cross-checked by " + c.formulation + " (max difference " +
                                   num(ref.cross_check) + ")";
            } catch (const std::exception& e) {
                ref.description += ", cross-check by " + c.formulation + " failed: " + e.what();
            }
        }
    }
    return ref;
}

BenchSceneResult run_bench_scene(const std::string& scene_file, Registry& registry, const BenchOptions& options,
                                 const std::function<void(const std::string&)>& log) {
    BenchSceneResult out;
    out.spec = load_bench_spec(scene_file);
    const BenchSpec& spec = out.spec;
    const Model model = load_scene(scene_file, registry);
    auto note = [&](const std::string& text) {
        out.notes.push_back(text);
        if (log) log(text);
    };
    out.reference = make_bench_reference(model, registry, spec);
    const std::string measure = spec.measure.describe();
    const std::vector<double> times = bench_output_times(spec);

    int total = 0;
    auto wanted = [&](const std::string& f) {
        return options.only_formulations.empty() ||
               std::find(options.only_formulations.begin(), options.only_formulations.end(), f) !=
                   options.only_formulations.end();
    };
    for (const auto& s : spec.runs)
        if (wanted(s.formulation)) total += static_cast<int>(s.tolerances.size() + s.steps.size());
    for (const auto& p : spec.peers) total += static_cast<int>(p.tolerances.size() + p.steps.size());
    GridProgress progress(options.progress, spec.name, total);
    int done = 0;

    const int repeat = std::max(1, options.repeat);
    for (const auto& series : spec.runs) {
        if (!wanted(series.formulation)) continue;
        std::vector<std::pair<bool, double>> grid;
        for (double t : series.tolerances)
            if (t >= options.tolerance_floor) grid.push_back({true, t});
        for (double h : series.steps) grid.push_back({false, h});
        bool failed_before = false;  // a failed (or very slow) point: tighter ones are skipped
        for (const auto& [adaptive, value] : grid) {
            progress.update(done++, series.formulation + " " + series.integrator + " " + num(value));
            BenchRow row;
            row.scene = spec.name;
            row.formulation = series.formulation;
            row.integrator = series.integrator;
            row.tolerance = adaptive ? value : 0.0;
            row.step = adaptive ? 0.0 : value;
            row.error_measure = measure;
            row.reference_kind = out.reference.kind;
            if (failed_before) {
                row.status = "skipped (a looser point of this series failed)";
                row.error = std::numeric_limits<double>::quiet_NaN();
                out.rows.push_back(row);
                continue;
            }
            SimulationSettings s;
            s.formulation = series.formulation;
            s.integrator = series.integrator;
            if (adaptive) s.integration.tolerance = value;
            else s.integration.step = value;
            s.t_end = spec.t_end;
            s.output_step = times.front();
            s.progress = false;
            std::vector<double> cpu;
            try {
                for (int k = 0; k < repeat; ++k) {
                    SimulationResult r;
                    const Trajectory tr = sample_trajectory(model, registry, s, spec.measure, r);
                    cpu.push_back(r.cpu_seconds);
                    row.steps = r.stats.steps;
                    if (k == 0) row.error = bench_error(tr, out.reference.trajectory, spec.measure);
                    if (r.cpu_seconds > 1.0) break;  // slow points are timed once
                }
                row.cpu_s = median(cpu);
                if (!std::isfinite(row.error)) row.status = "failed: non-finite error";
            } catch (const std::exception& e) {
                row.status = std::string("failed: ") + e.what();
                row.error = std::numeric_limits<double>::quiet_NaN();
                failed_before = true;
            }
            out.rows.push_back(row);
        }
    }

    // peers
    for (const auto& series : spec.peers) {
        const std::string exe =
            options.peers_dir.empty() ? std::string() : options.peers_dir + "/mbd_peer_" + series.engine;
        if (exe.empty() || !std::filesystem::exists(exe)) {
            done += static_cast<int>(series.tolerances.size() + series.steps.size());
            const std::string text = "peer " + series.engine + ": not installed (" +
                                     (exe.empty() ? std::string("no --peers directory given")
                                                  : "no " + exe + "; install lib" + series.engine +
                                                        "-dev and rebuild bench/peers") +
                                     "); skipped";
            if (std::find(out.notes.begin(), out.notes.end(), text) == out.notes.end()) note(text);
            continue;
        }
        std::vector<std::pair<bool, double>> grid;
        for (double t : series.tolerances) grid.push_back({true, t});
        for (double h : series.steps) grid.push_back({false, h});
        for (const auto& [adaptive, value] : grid) {
            progress.update(done++, series.engine + " " + series.integrator + " " + num(value));
            BenchRow row;
            row.engine = series.engine;
            row.scene = spec.name;
            row.formulation = series.engine;
            row.integrator = series.integrator;
            row.tolerance = adaptive ? value : 0.0;
            row.step = adaptive ? 0.0 : value;
            row.error_measure = measure;
            row.reference_kind = out.reference.kind;
            std::vector<double> cpu;
            for (int k = 0; k < repeat; ++k) {
                const PeerRun r = run_peer(exe, spec.peer_model + ":" + series.integrator, spec.t_end, times.front(),
                                           adaptive, value, static_cast<int>(spec.measure.bodies.size()));
                if (!r.ok) {
                    row.status = "failed: " + r.message;
                    row.error = std::numeric_limits<double>::quiet_NaN();
                    break;
                }
                cpu.push_back(r.cpu_s);
                row.steps = r.steps;
                if (k == 0) {
                    try {
                        row.error = bench_error(r.trajectory, out.reference.trajectory, spec.measure);
                    } catch (const std::exception& e) {
                        row.status = std::string("failed: ") + e.what();
                        row.error = std::numeric_limits<double>::quiet_NaN();
                        break;
                    }
                }
                if (r.cpu_s > 1.0) break;
            }
            row.cpu_s = median(cpu);
            out.rows.push_back(row);
        }
    }
    progress.finish();
    return out;
}

std::string bench_csv(const std::vector<BenchSceneResult>& results) {
    std::ostringstream f;
    f << "engine,scene,formulation,integrator,tolerance,step,cpu_s,steps,error,error_measure,reference_kind,status\n";
    for (const auto& r : results)
        for (const auto& row : r.rows)
            f << row.engine << ',' << csv_field(row.scene) << ',' << row.formulation << ',' << row.integrator << ','
              << (row.tolerance > 0 ? json_number(row.tolerance) : "") << ','
              << (row.step > 0 ? json_number(row.step) : "") << ',' << json_number(row.cpu_s) << ',' << row.steps
              << ',' << (std::isfinite(row.error) ? json_number(row.error) : "") << ','
              << csv_field(row.error_measure) << ',' << row.reference_kind << ',' << csv_field(row.status) << '\n';
    return f.str();
}

std::string bench_json(const std::vector<BenchSceneResult>& results) {
    std::ostringstream f;
    f << "{\n  \"scenes\": [\n";
    for (size_t i = 0; i < results.size(); ++i) {
        const auto& r = results[i];
        f << "    {\"scene\": \"" << json_escape(r.spec.name) << "\", \"file\": \"" << json_escape(r.spec.scene)
          << "\", \"t_end\": " << json_number(r.spec.t_end) << ", \"error_measure\": \""
          << json_escape(r.spec.measure.describe()) << "\", \"reference_kind\": \"" << r.reference.kind
          << "\", \"reference\": \"" << json_escape(r.reference.description) << "\", \"cross_check\": "
          << (r.reference.cross_check >= 0 ? json_number(r.reference.cross_check) : "null") << ", \"notes\": [";
        for (size_t k = 0; k < r.notes.size(); ++k) f << (k ? ", " : "") << '"' << json_escape(r.notes[k]) << '"';
        f << "]}" << (i + 1 < results.size() ? "," : "") << '\n';
    }
    f << "  ],\n  \"rows\": [\n";
    bool first = true;
    for (const auto& r : results)
        for (const auto& row : r.rows) {
            f << (first ? "" : ",\n") << "    {\"engine\": \"" << row.engine << "\", \"scene\": \""
              << json_escape(row.scene) << "\", \"formulation\": \"" << row.formulation << "\", \"integrator\": \""
              << row.integrator << "\", \"tolerance\": " << (row.tolerance > 0 ? json_number(row.tolerance) : "null")
              << ", \"step\": " << (row.step > 0 ? json_number(row.step) : "null")
              << ", \"cpu_s\": " << json_number(row.cpu_s) << ", \"steps\": " << row.steps
              << ", \"error\": " << json_number(row.error) << ", \"error_measure\": \""
              << json_escape(row.error_measure) << "\", \"reference_kind\": \"" << row.reference_kind
              << "\", \"status\": \"" << json_escape(row.status) << "\"}";
            first = false;
        }
    f << "\n  ]\n}\n";
    return f.str();
}

}  // namespace mbd
