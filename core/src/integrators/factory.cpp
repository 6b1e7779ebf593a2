// make_integrator / integrator_names: the integrators by name.
#include "common.hpp"

#include <mbd/sdk/formulation.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <cstdio>

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
    {"dop853", &integrators::make_dop853},
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

std::string command_line_spelling(const std::string& option, const std::string& value) {
    return "--" + option + (value.empty() ? std::string() : " " + value);
}

void check_integrator_options(const std::string& integrator, bool tolerance_given, double tolerance, bool step_given,
                              double step, double t_end, const OptionSpelling& spell) {
    // no integrator named: the automatic choice (method_choice.hpp), always an adaptive one
    const bool automatic = integrator.empty();
    const std::string who = automatic ? "the automatic integrator (dopri5 or cvode)" : integrator;
    const bool adaptive = automatic || make_integrator(integrator, IntegratorSettings{})->adaptive();
    if (adaptive && step_given)
        throw InputError(spell("step", ""), "applies to the fixed-step integrators (rk4, euler, generalized_alpha); " +
                                                who + " chooses its own steps: set its accuracy with " +
                                                spell("tol", "") + " and the time between rows with " +
                                                spell("output-step", "") +
                                                (automatic ? ", or name a fixed-step one with " + spell("integrator", "rk4")
                                                           : std::string()));
    if (!adaptive && tolerance_given)
        throw InputError(spell("tol", ""), "applies to the adaptive integrators (dopri5, dop853, cvode); " + integrator +
                                               " takes fixed steps: set them with " + spell("step", ""));
    if (!adaptive && !step_given)
        throw InputError(spell("step", ""), integrator + " takes fixed steps: give their size with " +
                                                spell("step", "") + " (e.g. " + spell("step", "1e-3") +
                                                "), or choose an adaptive integrator (" +
                                                spell("integrator", "dopri5") + ", dop853 or cvode)");
    if (tolerance_given && !(tolerance >= kSmallestTolerance && tolerance <= 1.0))
        throw InputError(spell("tol", ""), "expected a number from 1e-14 to 1 (below 1e-14 is beneath "
                                           "double-precision round-off), got " + format_number(tolerance));
    if (step_given) {
        if (!(std::isfinite(step) && step > 0.0))
            throw InputError(spell("step", ""), "expected a positive number, got " + format_number(step));
        const double steps = t_end / step;
        const long limit = IntegratorSettings{}.max_steps;
        if (!(steps <= static_cast<double>(limit))) {
            char text[200];
            std::snprintf(text, sizeof text, "%g needs %.3g steps to reach %s %g; at most %ld are taken: use a "
                          "larger step", step, steps, spell("t-end", "").c_str(), t_end, limit);
            throw InputError(spell("step", ""), text);
        }
    }
}

}  // namespace mbd
