// make_integrator / integrator_names: the integrators by name.
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

}  // namespace mbd
