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
//   {type: input,      name: NAME}                               the value a program sets (Simulator::set_input)
// A bare number is a constant.
#pragma once

#include <mbd/sdk/params.hpp>

#include <memory>
#include <string>

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

// The values a program sets while it steps a simulation (Simulator::set_input,
// docs/embedding.md): a time function {type: input, name: NAME} is the value named NAME of
// the table current on the evaluating thread, held (zero rate and acceleration) until the
// program changes it. A Simulator makes its own table current while it evaluates, so two
// Simulators of one Model never share inputs. With none current, evaluating one is an InputError.
class MBD_SDK_API InputValues {
public:
    virtual ~InputValues() = default;
    // Throws InputError for a name the table does not have, listing the names it has.
    virtual double value(const std::string& name) const = 0;
};

// The table current on this thread (null: none). Default visibility: one variable for the
// host and every plugin.
MBD_SDK_API inline const InputValues*& current_input_values() {
    static thread_local const InputValues* current = nullptr;
    return current;
}

// Build a time function from its scene node (a map with `type`, or a number).
// `what` names the element for error messages. Throws InputError.
inline std::shared_ptr<const TimeFunction> make_time_function(const Param& node, const std::string& what);

}  // namespace mbd

#include <mbd/sdk/detail/time_function_impl.hpp>
