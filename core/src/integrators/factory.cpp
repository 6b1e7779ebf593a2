// make_integrator / integrator_names, and the helpers shared by the integrators.
#include "common.hpp"

#include <mbd/sdk/formulation.hpp>

namespace mbd {

namespace {

struct Entry {
    const char* name;
    std::unique_ptr<Integrator> (*make)(const IntegratorSettings&);
};

const Entry kIntegrators[] = {
    {"euler", &integrators::make_euler},
    {"rk4", &integrators::make_rk4},
    {"dopri5", &integrators::make_dopri5},
    {"generalized_alpha", &integrators::make_generalized_alpha},
    {"cvode", &integrators::make_cvode},
};

}  // namespace

std::vector<std::string> integrator_names() {
    std::vector<std::string> names;
    for (const Entry& e : kIntegrators) names.emplace_back(e.name);
    return names;
}

std::unique_ptr<Integrator> make_integrator(const std::string& name, const IntegratorSettings& settings) {
    for (const Entry& e : kIntegrators)
        if (name == e.name) return e.make(settings);
    std::string known;
    for (const Entry& e : kIntegrators) known += std::string(known.empty() ? "" : ", ") + e.name;
    throw InputError("integrator", "unknown integrator '" + name + "' (known: " + known + ")");
}

namespace integrators {

void check_output_times(const std::string& integrator, double t0, const std::vector<double>& output_times) {
    double previous = t0;
    for (double t : output_times) {
        if (!std::isfinite(t) || t < previous)
            throw InputError(integrator, "output times must be finite and must not decrease from the start time " +
                                             format_time(t0) + " (got " + format_time(t) + " after " +
                                             format_time(previous) + ")");
        previous = t;
    }
}

void BlowUpGuard::check(double t, const Eigen::VectorXd& y) const {
    const bool finite = y.allFinite();
    if (!finite || y.lpNorm<Eigen::Infinity>() > limit_)
        throw DynamicsError(t, std::string("state ") + (finite ? "grew without bound" : "became non-finite") +
                                   " at t = " + format_time(t) +
                                   ": step too large for this stiff problem (use a smaller step, or "
                                   "--integrator generalized_alpha or cvode)");
}

void project_or_throw(OdeProblem& problem, double t, Eigen::VectorXd& y) {
    if (!problem.project(t, y))
        throw DynamicsError(t, "projection onto the constraint manifold failed at t = " + format_time(t));
}

}  // namespace integrators
}  // namespace mbd
