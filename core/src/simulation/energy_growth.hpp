// Watches the total energy T + V of a forward-dynamics run whose scene is
// conservative (every force conservative, no drivers, no time-dependent
// constraint), where it must stay constant: a run whose energy grows far beyond the
// scale of its motion is numerically unstable, and is stopped with that diagnosis
// instead of writing a motion that gains energy without bound.
#pragma once

#include <mbd/kit/formulation.hpp>

#include <string>

namespace mbd {

class EnergyGrowthWatch {
public:
    // The gain E - E0 that stops the run, as a multiple of the energy scale of the motion.
    static constexpr double kLimit = 100.0;

    // `conservative`: no energy may enter (else the watch does nothing).
    explicit EnergyGrowthWatch(bool conservative) : active_(conservative) {}
    // One output sample (the first gives E0); throws DynamicsError when E - E0 exceeds
    // kLimit times the energy scale. `time_dependent`: a constraint moved with time at
    // this sample (work enters through it), which switches the watch off.
    void check(double t, double kinetic, double potential, bool time_dependent, const std::string& advice);
    bool active() const { return active_; }

private:
    bool active_;
    bool started_ = false;
    double kinetic0_ = 0.0, potential0_ = 0.0;
    // The energy scale of the motion: |T0|, |V0|, |E0| and the largest T and |V - V0| seen
    // while the energy still held (gain within 10 % of the scale), so that an instability
    // cannot raise it.
    double scale_ = 0.0;
};

}  // namespace mbd
