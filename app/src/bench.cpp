// Work-precision benchmarks (see bench.hpp).
#include <mbd/app/bench.hpp>
#include <mbd/app/json_output.hpp>

#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/progress_bar.hpp>

#include <mbd/scene.hpp>
#include <mbd/sdk/number.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

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
                 double value, int points, const std::vector<std::string>& arguments) {
    PeerRun r;
    const auto quoted = [](const std::string& word) {
        std::string out = "'";
        for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
        return out + "'";
    };
    std::string cmd = quoted(exe) + " " + quoted(model) + " " + format_number(t_end) + " " + format_number(output_step) + " " +
                      (tolerance ? "tol " : "step ") + format_number(value);
    for (const std::string& word : arguments) cmd += " " + quoted(word);
    cmd += " 2>&1";
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

// A series' grid: its tolerances (adaptive, those not below `tolerance_floor`), then its steps.
std::vector<std::pair<bool, double>> grid_points(const std::vector<double>& tolerances, const std::vector<double>& steps,
                                                 double tolerance_floor) {
    std::vector<std::pair<bool, double>> grid;
    for (double t : tolerances)
        if (t >= tolerance_floor) grid.push_back({true, t});
    for (double h : steps) grid.push_back({false, h});
    return grid;
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
        if (!points[i].isZero()) who += " point (" + format_number(points[i].x()) + ", " + format_number(points[i].y()) + ", " +
                                        format_number(points[i].z()) + ")";
    }
    return (norm == "final" ? "final |r - r_ref| of " : "max |r - r_ref| over the output times of ") + who;
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
            throw std::invalid_argument("bench_error: the run has no sample at t = " + format_number(t));
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
        s.messages = MessageLog::silent();  // one line per run would bury the bar; each row has its status
        SimulationResult r;
        ref.trajectory = sample_trajectory(model, registry, s, spec.measure, r);
        ref.description = "tight run: " + s.formulation + " + " + s.integrator + " at tol " +
                          format_number(spec.reference.tolerance);
        if (!spec.reference.cross_check.empty() && spec.reference.cross_check != "none") {
            SimulationSettings c = s;
            c.formulation = spec.reference.cross_check;
            try {
                const Trajectory other = sample_trajectory(model, registry, c, spec.measure, r);
                ref.cross_check = bench_error(other, ref.trajectory, BenchMeasure{spec.measure.bodies,
                                                                                  spec.measure.points, "position", "max"});
                ref.description += ", cross-checked by " + c.formulation + " (max difference " +
                                   format_number(ref.cross_check) + ")";
            } catch (const std::exception& e) {
                ref.description += ", cross-check by " + c.formulation + " failed: " + e.what();
            }
        }
    }
    return ref;
}

namespace {

// Times one grid point of an mbd series: `repeat` runs (slow ones once), the CPU time
// their median, the error of the first. False when the run failed (row.status says why).
bool time_mbd_point(const Model& model, Registry& registry, const BenchSpec& spec, const BenchSeries& series,
                    const Trajectory& reference, double output_step, bool adaptive, double value, int repeat,
                    BenchRow& row) {
    SimulationSettings s;
    s.formulation = series.formulation;
    s.integrator = series.integrator;
    if (adaptive) s.integration.tolerance = value;
    else s.integration.step = value;
    s.t_end = spec.t_end;
    s.output_step = output_step;
    s.progress = false;
    s.messages = MessageLog::silent();  // one line per run would bury the bar; each row has its status
    std::vector<double> cpu;
    try {
        for (int k = 0; k < repeat; ++k) {
            SimulationResult r;
            const Trajectory tr = sample_trajectory(model, registry, s, spec.measure, r);
            cpu.push_back(r.cpu_seconds);
            row.steps = r.stats.steps;
            if (k == 0) row.error = bench_error(tr, reference, spec.measure);
            if (r.cpu_seconds > 1.0) break;  // slow points are timed once
        }
        row.cpu_s = median(cpu);
        if (!std::isfinite(row.error)) row.status = "failed: non-finite error";
    } catch (const std::exception& e) {
        row.status = std::string("failed: ") + e.what();
        row.error = std::numeric_limits<double>::quiet_NaN();
        return false;
    }
    return true;
}

// The same for a peer program `exe`.
void time_peer_point(const std::string& exe, const BenchSpec& spec, const BenchPeerSeries& series,
                     const Trajectory& reference, double output_step, bool adaptive, double value, int repeat,
                     BenchRow& row) {
    std::vector<double> cpu;
    for (int k = 0; k < repeat; ++k) {
        const PeerRun r = run_peer(exe, spec.peer_model + ":" + series.integrator, spec.t_end, output_step, adaptive,
                                   value, static_cast<int>(spec.measure.bodies.size()), spec.peer_arguments);
        if (!r.ok) {
            row.status = "failed: " + r.message;
            row.error = std::numeric_limits<double>::quiet_NaN();
            break;
        }
        cpu.push_back(r.cpu_s);
        row.steps = r.steps;
        if (k == 0) {
            try {
                row.error = bench_error(r.trajectory, reference, spec.measure);
            } catch (const std::exception& e) {
                row.status = std::string("failed: ") + e.what();
                row.error = std::numeric_limits<double>::quiet_NaN();
                break;
            }
        }
        if (r.cpu_s > 1.0) break;
    }
    row.cpu_s = median(cpu);
}

}  // namespace

BenchSceneResult run_bench_scene(const std::string& scene_file, Registry& registry, const BenchOptions& options,
                                 const std::function<void(const std::string&)>& log) {
    const Scene scene = read_scene(scene_file, registry);
    return run_bench(scene.model, load_bench_spec(scene), registry, options, log);
}

BenchSceneResult run_bench(const Model& model, const BenchSpec& bench_spec, Registry& registry, const BenchOptions& options,
                           const std::function<void(const std::string&)>& log) {
    BenchSceneResult out;
    out.spec = bench_spec;
    const BenchSpec& spec = out.spec;
    out.automatic = automatic_method(model, spec.t_end);
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
        if (wanted(s.formulation))
            total += static_cast<int>(grid_points(s.tolerances, s.steps, options.tolerance_floor).size());
    for (const auto& p : spec.peers)
        total += static_cast<int>(grid_points(p.tolerances, p.steps, options.tolerance_floor).size());
    GridProgress progress(options.progress, spec.name, total);
    int done = 0;

    const int repeat = std::max(1, options.repeat);
    // The row of one grid point (a tolerance when adaptive, else a step), announced on the progress bar.
    auto grid_row = [&](const std::string& engine, const std::string& formulation, const std::string& integrator,
                        bool adaptive, double value) {
        progress.update(done++, formulation + " " + integrator + " " + format_number(value));
        BenchRow row;
        row.engine = engine;
        row.scene = spec.name;
        row.formulation = formulation;
        row.integrator = integrator;
        row.tolerance = adaptive ? value : 0.0;
        row.step = adaptive ? 0.0 : value;
        row.error_measure = measure;
        row.reference_kind = out.reference.kind;
        return row;
    };
    for (const auto& series : spec.runs) {
        if (!wanted(series.formulation)) continue;
        bool failed_before = false;  // a failed (or very slow) point: tighter ones are skipped
        for (const auto& [adaptive, value] : grid_points(series.tolerances, series.steps, options.tolerance_floor)) {
            BenchRow row = grid_row("mbd", series.formulation, series.integrator, adaptive, value);
            if (failed_before) {
                row.status = "skipped (a looser point of this series failed)";
                row.error = std::numeric_limits<double>::quiet_NaN();
            } else if (!time_mbd_point(model, registry, spec, series, out.reference.trajectory, times.front(),
                                       adaptive, value, repeat, row)) {
                failed_before = true;
            }
            out.rows.push_back(row);
        }
    }

    for (const auto& series : spec.peers) {
        std::string missing;
        const std::string exe = peer_executable(options.peer_dirs, series.engine, missing);
        const auto grid = grid_points(series.tolerances, series.steps, options.tolerance_floor);
        if (exe.empty()) {
            const int points = static_cast<int>(grid.size());
            done += points;
            out.skipped_peer_runs += points;
            if (std::find(out.notes.begin(), out.notes.end(), missing) == out.notes.end()) note(missing);
            continue;
        }
        for (const auto& [adaptive, value] : grid) {
            BenchRow row = grid_row(series.engine, series.engine, series.integrator, adaptive, value);
            time_peer_point(exe, spec, series, out.reference.trajectory, times.front(), adaptive, value, repeat, row);
            out.rows.push_back(row);
        }
    }
    progress.finish();
    return out;
}

BenchTally tally(const BenchSceneResult& result) {
    BenchTally t;
    for (const BenchRow& row : result.rows) {
        if (row.status == "ok") ++t.ok;
        else if (row.status.rfind("skipped", 0) == 0) ++t.skipped;
        else ++t.failed;
    }
    t.skipped_peers = result.skipped_peer_runs;
    return t;
}

std::string bench_csv(const std::vector<BenchSceneResult>& results) {
    std::ostringstream f;
    f << "engine,scene,formulation,integrator,tolerance,step,cpu_s,steps,error,error_measure,reference_kind,status\n";
    for (const auto& r : results)
        for (const auto& row : r.rows)
            f << row.engine << ',' << csv_field(row.scene) << ',' << row.formulation << ',' << row.integrator << ','
              << (row.tolerance > 0 ? format_number(row.tolerance, 9) : "") << ','
              << (row.step > 0 ? format_number(row.step, 9) : "") << ',' << format_number(row.cpu_s, 9) << ','
              << row.steps << ',' << (std::isfinite(row.error) ? format_number(row.error, 9) : "") << ','
              << csv_field(row.error_measure) << ',' << row.reference_kind << ',' << csv_field(row.status) << '\n';
    return f.str();
}

// Absent values (no tolerance on a fixed-step run, no cross-check) are null; a failed run's
// error is NaN, written null and listed under "non_finite" (json_output.hpp), its row's
// status saying why.
std::string bench_json(const std::vector<BenchSceneResult>& results) {
    Json scenes = Json::array(), rows = Json::array();
    auto positive_or_null = [](double x) { return x > 0 ? Json(x) : Json(nullptr); };
    for (const auto& r : results) {
        scenes.push_back({{"scene", r.spec.name},
                          {"file", r.spec.scene},
                          {"t_end", r.spec.t_end},
                          {"automatic", {{"formulation", r.automatic.formulation},
                                         {"integrator", r.automatic.integrator},
                                         {"formulation_reason", r.automatic.formulation_reason},
                                         {"integrator_reason", r.automatic.integrator_reason}}},
                          {"error_measure", r.spec.measure.describe()},
                          {"reference_kind", r.reference.kind},
                          {"reference", r.reference.description},
                          {"cross_check", r.reference.cross_check >= 0 ? Json(r.reference.cross_check) : Json(nullptr)},
                          {"notes", r.notes}});
        for (const auto& row : r.rows)
            rows.push_back({{"engine", row.engine},
                            {"scene", row.scene},
                            {"formulation", row.formulation},
                            {"integrator", row.integrator},
                            {"tolerance", positive_or_null(row.tolerance)},
                            {"step", positive_or_null(row.step)},
                            {"cpu_s", row.cpu_s},
                            {"steps", row.steps},
                            {"error", row.error},
                            {"error_measure", row.error_measure},
                            {"reference_kind", row.reference_kind},
                            {"status", row.status}});
    }
    return json_text({{"scenes", std::move(scenes)}, {"rows", std::move(rows)}}, 2) + "\n";
}

}  // namespace mbd
