// The right-hand side is not finite at the state it was asked for: the motion diverged there. At a
// trial state of an adaptive step this only says the step was too long, so the adaptive integrators
// reject the step and retry shorter (core/src/integrators: embedded_runge_kutta.cpp, cvode.cpp);
// everywhere else it stops the run like any DynamicsError.
#pragma once

#include <mbd/kit/formulation.hpp>

namespace mbd {

class MBD_SDK_API NonFiniteMotion : public DynamicsError {
public:
    using DynamicsError::DynamicsError;
};

}  // namespace mbd
