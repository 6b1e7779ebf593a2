// Stability matrix of the extreme cases (issue 8); see mbd/app/stability.hpp.
#include <mbd/app/stability.hpp>

#include <mbd/app/failure_kind.hpp>
#include <mbd/sdk/text.hpp>

#include <mbd/interrupt.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/model_system.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/sdk/params.hpp>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include <Eigen/Geometry>

#include <ctime>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

namespace mbd {

namespace {

const std::vector<std::string> kKinds = {"step_size_collapse", "newton_divergence", "singular_constraints",
                                         "redundant_constraints", "assembly_failure", "projection_failure",
                                         "blow_up", "max_steps", "solver_failure", "budget_exceeded",
                                         "singular_mass_matrix"};

const Param* field(const Param& node, const std::string& key) {
    auto it = node.fields.find(key);
    return it == node.fields.end() ? nullptr : &it->second;
}

double number_or(const Param& node, const std::string& key, double fallback) {
    const Param* p = field(node, key);
    return p ? p->as_number("expect." + key) : fallback;
}

std::string text_or(const Param& node, const std::string& key, const std::string& fallback) {
    const Param* p = field(node, key);
    if (!p) return fallback;
    if (!p->is_scalar()) p->fail("expect." + key + " must be a name");
    return p->text;
}

std::vector<std::string> kind_list(const Param& p, const std::string& what) {
    std::vector<std::string> out;
    if (p.is_scalar()) out.push_back(p.text);
    else if (p.is_list())
        for (const Param& item : p.items) {
            if (!item.is_scalar()) item.fail(what + " must be failure kinds");
            out.push_back(item.text);
        }
    else p.fail(what + " must be a failure kind or a list of them");
    for (const std::string& k : out)
        if (std::find(kKinds.begin(), kKinds.end(), k) == kKinds.end()) {
            std::string known;
            for (const auto& n : kKinds) known += (known.empty() ? "" : ", ") + n;
            p.fail(what + ": unknown failure kind '" + k + "'; known: " + known);
        }
    return out;
}

Mat3 rotation_matrix(const Eigen::VectorXd& q, int offset) {
    Eigen::Quaterniond e(q[offset + 3], q[offset + 4], q[offset + 5], q[offset + 6]);
    return e.normalized().toRotationMatrix();
}

// expect.final: {bodies: [...], positions: [...]}, one position (world, metres) per body.
void read_final_positions(const Param& m, const Model& model, Expectation& e) {
    const Param* bodies = field(m, "bodies");
    const Param* positions = field(m, "positions");
    if (!bodies || !bodies->is_list() || !positions || !positions->is_list() ||
        bodies->items.size() != positions->items.size())
        m.fail("expect.final needs bodies: [NAME, ...] and as many positions: [[x, y(, z)], ...]");
    const int n = model.dimension == Dimension::Planar ? 2 : 3;
    for (size_t k = 0; k < bodies->items.size(); ++k) {
        const Param& b = bodies->items[k];
        if (!b.is_scalar() || model.body_index(b.text) < 0) b.fail("expect.final: unknown body '" + b.text + "'");
        const Eigen::VectorXd p = positions->items[k].as_vector("expect.final.positions", n);
        e.final_bodies.push_back(b.text);
        e.final_positions.push_back(n == 2 ? Vec3(p[0], p[1], 0.0) : Vec3(p[0], p[1], p[2]));
    }
}

}  // namespace

Expectation read_expectation(const Scene& scene) {
    const Model& model = scene.model;
    const Param* section = scene.section(kExpectSection);
    if (!section) throw InputError(model.source, "the scene has no 'expect:' key (declared outcome)");
    const Param& node = *section;
    if (!node.is_map()) node.fail("'expect' must be a map: {outcome: pass | failure, ...}");
    Expectation e;
    const Param* outcome = field(node, "outcome");
    if (!outcome || !outcome->is_scalar() || (outcome->text != "pass" && outcome->text != "failure"))
        node.fail("expect.outcome must be 'pass' or 'failure'");
    e.pass = outcome->text == "pass";
    if (e.pass) {
        if (const Param* a = field(node, "also_accept")) e.kinds = kind_list(*a, "expect.also_accept");
    } else {
        const Param* k = field(node, "kind");
        if (!k) node.fail("expect: a failure needs 'kind' (one failure kind or a list)");
        e.kinds = kind_list(*k, "expect.kind");
    }
    e.measure = text_or(node, "measure", e.measure);
    const std::vector<std::string> measures = {"oscillator", "energy", "momentum", "rotation",
                                               "a01", "final", "constraints"};
    if (std::find(measures.begin(), measures.end(), e.measure) == measures.end())
        node.fail("expect.measure '" + e.measure +
                  "' is unknown; known: oscillator, energy, momentum, rotation, a01, final, constraints");
    e.bound = number_or(node, "bound", e.bound);
    e.formulation = text_or(node, "formulation", e.formulation);
    e.integrator = text_or(node, "integrator", e.integrator);
    e.t_end = number_or(node, "t_end", e.t_end);
    e.quick_t_end = number_or(node, "quick_t_end", e.t_end);
    e.output_step = number_or(node, "output_step", 0.0);
    e.tolerance = number_or(node, "tolerance", e.tolerance);
    e.step = number_or(node, "step", 0.0);
    e.rho_infinity = number_or(node, "rho_infinity", e.rho_infinity);
    e.budget = number_or(node, "budget", e.budget);
    if (const Param* m = field(node, e.measure)) {
        if (!m->is_map()) m->fail("expect." + e.measure + " must be a map");
        e.body = text_or(*m, "body", "");
        e.amplitude = number_or(*m, "amplitude", 0.0);
        e.omega = number_or(*m, "omega", 0.0);
        e.length = number_or(*m, "length", 1.0);
        if (const Param* a = field(*m, "axis")) e.axis = a->as_vector("expect." + e.measure + ".axis", 3).normalized();
        if (e.measure == "final") read_final_positions(*m, model, e);
    }
    if (e.measure == "final" && e.quick_t_end != e.t_end)
        node.fail("expect.final compares the positions at t_end, so quick_t_end must equal t_end");
    if (e.measure == "final" && e.final_bodies.empty())
        node.fail("expect.final needs {bodies: [NAME, ...], positions: [[x, y(, z)], ...]}");
    if ((e.measure == "oscillator" || e.measure == "rotation" || e.measure == "a01") && e.body.empty())
        node.fail("expect." + e.measure + " needs {body: NAME, ...}");
    if (!e.body.empty() && model.body_index(e.body) < 0)
        node.fail("expect: unknown body '" + e.body + "'");
    return e;
}

std::string CellOutcome::cell() const {
    std::string at = time >= 0.0 ? " at t = " + format_number(time, 3) : std::string();
    if (kind == "pass") return "pass (error " + format_number(error, 2) + ")";
    if (kind == "inaccurate") return "inaccurate (error " + format_number(error, 2) + " > " + format_number(bound, 2) + ")";
    if (kind == "crashed") return "crashed (signal " + std::to_string(signal) + ")";
    if (kind == "budget_exceeded") return "budget exceeded (" + format_number(seconds, 3) + " s" + at + ")";
    if (kind == "not_applicable") return "n/a (" + message + ")";
    std::string name = kind;
    std::replace(name.begin(), name.end(), '_', ' ');
    if (kind == "step_size_collapse") name = "step-size collapse";
    std::string detail;
    if (kind == "singular_constraints" || kind == "redundant_constraints") {
        // the engine names the dependent rows' joints; keep that part
        const size_t j = message.find("joint");
        if (j != std::string::npos) {
            detail = message.substr(j, 80);
            const size_t end = detail.find_first_of(";)\n");
            if (end != std::string::npos) detail = detail.substr(0, end);
            detail = ", " + detail;
        }
    }
    return name + at + detail;
}

std::vector<std::string> stability_integrators() {
    std::vector<std::string> names;
    for (const IntegratorDescription& d : integrator_descriptions())
        if (d.order >= 2) names.emplace_back(d.name);  // all but the first-order teaching method (euler)
    return names;
}

// The error measure of a case (its `expect:` key's `measure`), sample by sample: the worst
// error seen so far in `worst`.
class CaseMeasure {
public:
    CaseMeasure(const Model& model, const Expectation& e, double t_end)
        : model_(model), e_(e), t_end_(t_end), system_(model),
          body_(e.body.empty() ? -1 : model.body_index(e.body)) {}

    void sample(const State& st) {
        const bool planar = model_.dimension == Dimension::Planar;
        const Model& model = model_;
        const Expectation& e = e_;
        const int body = body_;
        if (e.measure == "oscillator") {
            const double x = st.q[model.q_offset(body)];
            worst = std::max(worst, std::abs(x - e.amplitude * std::cos(e.omega * st.t)) / std::abs(e.amplitude));
        } else if (e.measure == "energy") {
            const double T = system_.kinetic_energy(st), V = system_.potential_energy(st);
            if (first_) E0_ = T + V;
            scale_ = std::max(scale_, T + std::abs(V));
            if (scale_ > 0.0) worst = std::max(worst, std::abs(T + V - E0_) / scale_);
        } else if (e.measure == "momentum") {
            const double T = system_.kinetic_energy(st);
            Vec3 L = Vec3::Zero();
            for (int b = 0; b < model.body_count(); ++b) {
                const int qo = model.q_offset(b), vo = model.v_offset(b);
                const Vec3 R = st.q.segment<3>(qo), Rdot = st.v.segment<3>(vo), w = st.v.segment<3>(vo + 3);
                L += model.bodies[b].mass * R.cross(Rdot) + rotation_matrix(st.q, qo) * (model.bodies[b].inertia * w);
            }
            if (first_) T0_ = T, L0_ = L;
            worst = std::max({worst, std::abs(T - T0_) / std::max(T0_, 1e-300), (L - L0_).norm() / std::max(L0_.norm(), 1e-300)});
        } else if (e.measure == "rotation") {
            const Mat3 A = rotation_matrix(st.q, model.q_offset(body));
            const Vec4& p0 = model.bodies[body].euler_parameters;
            const Mat3 A0 = Eigen::Quaterniond(p0[0], p0[1], p0[2], p0[3]).normalized().toRotationMatrix();
            const Mat3 exact = Eigen::AngleAxisd(e.omega * st.t, e.axis).toRotationMatrix() * A0;
            worst = std::max(worst, (A - exact).cwiseAbs().maxCoeff());
        } else if (e.measure == "a01") {
            // compound pendulum pinned at the origin: J_O = J + m l^2, w^2 = m g l / J_O
            const Body& b = model.bodies[body];
            const double l = e.length, g = std::abs(model.gravity.y());
            const double w = std::sqrt(b.mass * g * l / (b.inertia(2, 2) + b.mass * l * l));
            const double k_mod = std::sin(M_PI / 4.0), K = boost::math::ellint_1(k_mod);
            const double theta = 2.0 * std::asin(k_mod * boost::math::jacobi_sn(k_mod, K - w * st.t));
            const int qo = model.q_offset(body);
            const double dx = st.q[qo] - l * std::sin(theta), dy = st.q[qo + 1] + l * std::cos(theta);
            worst = std::max(worst, std::hypot(dx, dy));
        } else if (e.measure == "final" && st.t >= t_end_ * (1.0 - 1e-12)) {
            for (size_t k = 0; k < e.final_bodies.size(); ++k) {
                const int qo = model.q_offset(model.body_index(e.final_bodies[k]));
                const Vec3 r = planar ? Vec3(st.q[qo], st.q[qo + 1], 0.0) : Vec3(st.q.segment<3>(qo));
                worst = std::max(worst, (r - e.final_positions[k]).norm());
            }
            reached_end = true;
        }
        first_ = false;
    }

    double worst = 0.0;
    bool reached_end = false;

private:
    const Model& model_;
    const Expectation& e_;
    double t_end_;
    ModelSystem system_;
    int body_;
    bool first_ = true;
    double E0_ = 0.0, scale_ = 0.0, T0_ = 0.0;
    Vec3 L0_ = Vec3::Zero();
};

namespace {

// This process's processor time (all its threads), in seconds.
double processor_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

CellOutcome run_case(const Model& model, Registry& registry, const Expectation& e, const std::string& formulation,
                     const std::string& integrator, double t_end, const CaseProgress& progress) {
    CellOutcome out;
    out.bound = e.bound;
    if (!(t_end > 0.0)) t_end = e.t_end;
    SimulationSettings s;
    s.formulation = formulation;
    s.integrator = integrator;
    s.t_end = t_end;
    s.output_step = e.output_step > 0.0 ? std::min(e.output_step, t_end) : t_end / 200.0;
    s.progress = false;
    s.messages = MessageLog::silent();
    s.integration.tolerance = e.tolerance;
    s.integration.rho_infinity = e.rho_infinity;
    if (!describe_integrator(integrator).adaptive)
        s.integration.step = e.step > 0.0 ? e.step : s.output_step / 10.0;

    CaseMeasure measure(model, e, t_end);
    bool over_budget = false;
    double last_t = 0.0;
    // The budget is the run's processor time, not wall time, so a cell's outcome does not depend on
    // what else the machine is doing (the matrix may run beside a build).
    const double start = processor_seconds();
    auto elapsed = [start] { return processor_seconds() - start; };

    auto callback = [&](const SimulationSample& sample) -> bool {
        last_t = sample.state.t;
        measure.sample(sample.state);
        if (progress) progress(last_t, t_end);
        if (elapsed() > e.budget) {
            over_budget = true;
            return false;
        }
        return true;
    };

    try {
        const SimulationResult r = simulate(model, registry, s, callback);
        out.seconds = elapsed();
        if (over_budget) {
            out.kind = "budget_exceeded";
            out.time = last_t;
            return out;
        }
        if (e.measure == "constraints") measure.worst = r.final_position_violation;
        if (e.measure == "final" && !measure.reached_end) measure.worst = std::numeric_limits<double>::infinity();
        const double worst = measure.worst;
        out.error = worst;
        out.kind = std::isfinite(worst) && worst <= e.bound ? "pass" : "inaccurate";
        if (!std::isfinite(worst)) out.kind = "blow_up";
    } catch (const KinematicsError& x) {
        out.kind = "assembly_failure";
        out.message = x.what();
        out.time = 0.0;
    } catch (const DynamicsError& x) {
        out.message = x.what();
        out.time = x.time();
        out.kind = failure_kind(out.message, false);
    } catch (const InputError& x) {
        out.message = x.what();
        if (out.message.find("velocity-level (nonholonomic)") != std::string::npos) {
            // a formulation or integrator that does not obey the scene's no-slip rows refuses it
            out.kind = "not_applicable";
            out.message = "no velocity-level rows";
        } else if (out.message.find("index-3") != std::string::npos) {
            out.kind = "not_applicable";
            out.message = "no index-3 form";
        } else if (out.message.find("does not locate events") != std::string::npos) {
            out.kind = "not_applicable";
            out.message = "no event location";
        } else {
            out.kind = "error";
        }
    } catch (const std::exception& x) {
        out.message = x.what();
        out.kind = "error";
    }
    out.seconds = elapsed();
    return out;
}

bool outcome_matches(const Expectation& e, const CellOutcome& o) {
    if (e.pass && o.kind == "pass") return true;
    return std::find(e.kinds.begin(), e.kinds.end(), o.kind) != e.kinds.end();
}

namespace {

// The matrix's adaptive (or fixed-step) integrators, as a list: "dopri5, dop853, cvode".
std::string integrators_where(const std::vector<std::string>& integrators, bool adaptive) {
    std::string list;
    for (const std::string& name : integrators)
        if (describe_integrator(name).adaptive == adaptive) list += (list.empty() ? "" : ", ") + name;
    return list;
}

}  // namespace

std::string stability_markdown(const std::vector<StabilityCase>& cases, const std::vector<std::string>& formulations,
                               const std::vector<std::string>& integrators, const std::string& command) {
    std::ostringstream md;
    md << "# Stability matrix of the extreme cases (issue 8)\n\n"
       << "Generated by `" << command << "` (app/src/stability.cpp, cli/stability_command.cpp); do not edit by "
       << "hand. Every scene of `scenes/extreme/` declares its expected outcome in its header comment and in its "
       << "`expect:` key; each cell is one run (a forked child with the case's processor-time budget) of that case with "
       << "one formulation and one integrator, at the case's tolerance (" << integrators_where(integrators, true)
       << ") or step (" << integrators_where(integrators, false) << ").\n\n"
       << "Cells: `pass (error E)` (the case's error measure within its bound), `inaccurate (error E > B)`, or a "
       << "named failure: step-size collapse, Newton divergence, singular constraints / redundant constraints "
       << "(naming the joints), assembly failure, projection failure, blow up (the state grew without bound), "
       << "max steps, solver failure, budget exceeded, singular mass matrix (a massless body), `n/a` (the integrator needs a form the formulation does "
       << "not have, event location the integrator lacks, or the pair does not handle the scene's velocity-level rows), `crashed (signal N)` (an engine defect). A `*` marks the declared pair; `ok`/`WRONG` says "
       << "whether the declared pair ended in a declared outcome.\n\n";
    int wrong = 0, crashes = 0;
    md << "| case | expected | declared |";
    for (const auto& f : formulations)
        for (const auto& i : integrators) md << " " << f << " + " << i << " |";
    md << "\n|---|---|---|";
    for (size_t k = 0; k < formulations.size() * integrators.size(); ++k) md << "---|";
    md << "\n";
    std::ostringstream notes;
    for (const StabilityCase& c : cases) {
        std::string expected;
        if (c.expect.pass) {
            expected = "pass: " + c.expect.measure + " <= " + format_number(c.expect.bound, 2);
            for (const auto& k : c.expect.kinds) expected += " or " + k;
        } else {
            for (const auto& k : c.expect.kinds) expected += (expected.empty() ? "" : " or ") + k;
        }
        std::string verdict = "not run";
        for (size_t fi = 0; fi < formulations.size(); ++fi)
            for (size_t ii = 0; ii < integrators.size(); ++ii) {
                const CellOutcome& o = c.cells[fi * integrators.size() + ii];
                if (o.kind == "crashed" || o.kind == "error") {
                    ++crashes;
                    notes << "- " << c.name << ", " << formulations[fi] << " + " << integrators[ii] << ": "
                          << o.cell() << (o.message.empty() ? "" : ": " + o.message) << "\n";
                }
                if (formulations[fi] == c.expect.formulation && integrators[ii] == c.expect.integrator)
                    verdict = outcome_matches(c.expect, o) ? "ok" : "WRONG";
            }
        if (verdict == "WRONG") ++wrong;
        md << "| " << c.name << " (t_end " << format_number(c.expect.t_end, 4) << " s) | " << expected << " | "
           << c.expect.formulation << " + " << c.expect.integrator << ": " << verdict << " |";
        for (size_t fi = 0; fi < formulations.size(); ++fi)
            for (size_t ii = 0; ii < integrators.size(); ++ii) {
                const CellOutcome& o = c.cells[fi * integrators.size() + ii];
                const bool declared = formulations[fi] == c.expect.formulation && integrators[ii] == c.expect.integrator;
                md << " " << o.cell() << (declared ? " *" : "") << " |";
            }
        md << "\n";
    }
    md << "\nSummary: " << cases.size() << " cases, " << wrong << " declared pairs not in a declared outcome, "
       << crashes << " crashes or unexpected errors.\n";
    if (crashes > 0) md << "\n## Crashes and unexpected errors (engine defects)\n\n" << notes.str();
    return md.str();
}

}  // namespace mbd
