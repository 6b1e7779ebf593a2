// Time functions f(t) with exact first and second derivatives, for drivers and
// for forces given as functions of time.
//
// Scene form (a map under `motion:`, `value:` and similar keys):
//   {type: constant,   value: c}
//   {type: linear,     initial: a, rate: b}                      f = a + b t
//   {type: polynomial, coefficients: [c0, c1, c2, ...]}          f = sum c_k t^k
//   {type: harmonic,   amplitude: A, frequency: w, phase: p, offset: c}   f = c + A sin(w t + p)  (w in rad/s)
//   {type: smooth_step, t0: .., t1: .., from: .., to: ..}        quintic, zero rate and acceleration at both ends
//   {type: spline,     table: [[t0, f0], [t1, f1], ...]}         natural cubic spline, linear extrapolation
// A bare number is a constant.
#pragma once

#include <mbd/sdk/params.hpp>

#include <memory>

namespace mbd {

struct TimeValue {
    double f = 0.0;
    double df = 0.0;   // df/dt
    double ddf = 0.0;  // d2f/dt2
};

class MBD_SDK_API TimeFunction {
public:
    virtual ~TimeFunction() = default;
    virtual TimeValue evaluate(double t) const = 0;
};

// Build a time function from its scene node (a map with `type`, or a number).
// `what` names the element for error messages. Throws InputError.
inline std::shared_ptr<const TimeFunction> make_time_function(const Param& node, const std::string& what);

}  // namespace mbd

#include <mbd/sdk/detail/time_function_impl.hpp>
