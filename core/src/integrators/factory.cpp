// make_integrator, the integrators' descriptions and the checks of their options, all read
// from the table (table.cpp).
#include "table.hpp"

#include <mbd/kit/formulation.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mbd {

std::vector<std::string> integrator_names() {
    std::vector<std::string> names;
    for (const integrators::IntegratorRow& row : integrators::integrator_table()) names.emplace_back(row.description.name);
    return names;
}

const std::vector<IntegratorDescription>& integrator_descriptions() {
    static const std::vector<IntegratorDescription> descriptions = [] {
        std::vector<IntegratorDescription> all;
        for (const integrators::IntegratorRow& row : integrators::integrator_table()) all.push_back(row.description);
        return all;
    }();
    return descriptions;
}

namespace {

const integrators::IntegratorRow& row_of(const std::string& name) {
    for (const integrators::IntegratorRow& row : integrators::integrator_table())
        if (name == row.description.name) return row;
    throw InputError("integrator", "unknown integrator '" + name + "' (known: " +
                                       integrator_list([](const IntegratorDescription&) { return true; }, ", ") + ")");
}

}  // namespace

const IntegratorDescription& describe_integrator(const std::string& name) { return row_of(name).description; }

std::string integrator_list(bool (*which)(const IntegratorDescription&), const std::string& last) {
    std::vector<std::string> names;
    for (const IntegratorDescription& d : integrator_descriptions())
        if (which(d)) names.emplace_back(d.name);
    std::string list;
    for (size_t i = 0; i < names.size(); ++i)
        list += (i == 0 ? "" : i + 1 == names.size() ? last : ", ") + names[i];
    return list;
}

const IntegratorDescription& automatic_integrator(bool stiff) {
    const auto wanted = stiff ? IntegratorDescription::Automatic::Stiff : IntegratorDescription::Automatic::NotStiff;
    for (const IntegratorDescription& d : integrator_descriptions())
        if (d.automatic == wanted) return d;
    throw std::logic_error("no integrator is the automatic choice for a scene that is " +
                           std::string(stiff ? "stiff" : "not stiff"));
}

std::unique_ptr<Integrator> make_integrator(const std::string& name, const IntegratorSettings& settings) {
    const integrators::IntegratorRow& row = row_of(name);
    std::unique_ptr<Integrator> integrator = row.make(settings);
    integrator->description_ = &row.description;
    return integrator;
}

std::string command_line_spelling(const std::string& option, const std::string& value) {
    return "--" + option + (value.empty() ? std::string() : " " + value);
}

void check_integrator_options(const std::string& integrator, bool tolerance_given, double tolerance, bool step_given,
                              double step, double t_end, const OptionSpelling& spell) {
    // no integrator named: the automatic choice (method_choice.hpp), always an adaptive one
    const bool automatic = integrator.empty();
    const auto is_adaptive = [](const IntegratorDescription& d) { return d.adaptive; };
    const auto is_fixed_step = [](const IntegratorDescription& d) { return !d.adaptive; };
    const auto is_automatic = [](const IntegratorDescription& d) {
        return d.automatic != IntegratorDescription::Automatic::Never;
    };
    const std::string who = automatic ? "the automatic integrator (" + integrator_list(is_automatic) + ")" : integrator;
    const bool adaptive = automatic || describe_integrator(integrator).adaptive;
    if (adaptive && step_given)
        throw InputError(spell("step", ""), "applies to the fixed-step integrators (" + integrator_list(is_fixed_step) +
                                                "); " + who + " chooses its own steps: set its accuracy with " +
                                                spell("tol", "") + " and the time between rows with " +
                                                spell("output-step", "") +
                                                (automatic ? ", or name a fixed-step one with " + spell("integrator", "rk4")
                                                           : std::string()));
    if (!adaptive && tolerance_given)
        throw InputError(spell("tol", ""), "applies to the adaptive integrators (" + integrator_list(is_adaptive) +
                                               "); " + integrator + " takes fixed steps: set them with " +
                                               spell("step", ""));
    if (!adaptive && !step_given)
        throw InputError(spell("step", ""), integrator + " takes fixed steps: give their size with " +
                                                spell("step", "") + " (e.g. " + spell("step", "1e-3") +
                                                "), or choose an adaptive integrator (" +
                                                spell("integrator", automatic_integrator(false).name) + "; adaptive: " +
                                                integrator_list(is_adaptive) + ")");
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
