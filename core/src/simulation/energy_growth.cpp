// Energy growth of a conservative run (see energy_growth.hpp).
#include "simulation/energy_growth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mbd {

void EnergyGrowthWatch::check(double t, double kinetic, double potential, bool time_dependent,
                              const std::string& advice) {
    if (!active_) return;
    if (time_dependent) {
        active_ = false;
        return;
    }
    if (!started_) {
        started_ = true;
        kinetic0_ = kinetic;
        potential0_ = potential;
        // the initial energies (the potential's zero is arbitrary: a large |V0| only makes
        // the watch less sensitive), and 1 nJ so that round-off in a scene at rest is no
        // "growth" (scenes are in SI units; no multibody motion lives below that)
        scale_ = std::max({std::abs(kinetic), std::abs(potential), std::abs(kinetic + potential), 1e-9});
        return;
    }
    const double gain = (kinetic + potential) - (kinetic0_ + potential0_);
    const double candidate = std::max({scale_, std::abs(kinetic), std::abs(potential - potential0_)});
    if (gain <= 0.1 * candidate) scale_ = candidate;  // the energy still holds: a trusted scale
    if (!(gain > kLimit * scale_)) return;            // (a NaN gain is left to the finiteness checks)
    char text[400];
    std::snprintf(text, sizeof text,
                  "the total energy T + V grew from %.6g to %.6g by t = %.6g, more than %g times the energy scale "
                  "of the motion (%.3g), although the scene is conservative (no drivers, no dampers or actuators): "
                  "the integration is unstable",
                  kinetic0_ + potential0_, kinetic + potential, t, kLimit, scale_);
    throw DynamicsError(t, text + (advice.empty() ? std::string() : "; " + advice));
}

}  // namespace mbd
