// The regularized Coulomb law with static and kinetic coefficients (book Eq. 5.74),
// as a friction coefficient of the sliding velocity v, for force elements.
//
// The book's law is set-valued at v = 0 (|F_f| <= mu_s F_n while stuck, F_f = mu_k F_n
// sgn(v) while sliding). An ODE needs a function, so within a named velocity scale
// v_s (`stiction_velocity`) the law rises to mu_s, and beyond it falls to mu_k:
//   x = v / v_s,
//   |x| <= 1:      mu(x) = mu_s (3 x - x^3) / 2           (rises to exactly mu_s, zero slope at |x| = 1)
//   1 < |x| <= 2:  mu(x) = sgn(x) mu_s                     (a plateau: a step that overshoots the
//                                                          stick band is pushed back, not released)
//   |x| >  2:      mu(x) = sgn(x) [mu_k + (mu_s - mu_k) exp(-(|x| - 2)^2)]     (C1 throughout)
// So a contact whose tangential load stays below mu_s F_n creeps at a speed below v_s
// (it "sticks" to within v_s; at exactly mu_s F_n within 2 v_s), the breakaway load is
// exactly mu_s F_n, and beyond 9 v_s the coefficient equals mu_k to double
// precision (exp(-49) < 6e-22).
// The slope at v = 0 is 1.5 mu_s F_n / v_s: a small v_s makes the problem stiff, for
// an implicit integrator (cvode).
#pragma once

#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/time_function.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace mbd::friction {

struct CoulombLaw {
    double mu_static = 0.0;
    double mu_kinetic = 0.0;
    double stiction_velocity = 1e-6;

    // the signed coefficient, templated for automatic differentiation
    template <class S>
    S coefficient(const S& v) const {
        using std::abs;
        using std::exp;
        using force_support::value_of;
        const S x = v / stiction_velocity;
        if (std::abs(value_of(x)) <= 1.0) return mu_static * (3.0 * x - x * x * x) / 2.0;
        if (std::abs(value_of(x)) <= 2.0) return S(value_of(x) > 0.0 ? mu_static : -mu_static);
        const S excess = abs(x) - 2.0;
        const S magnitude = mu_kinetic + (mu_static - mu_kinetic) * exp(-excess * excess);
        return value_of(x) > 0.0 ? magnitude : S(-magnitude);
    }

    // mu(|v|) / |v| of a slip velocity vector v, given its squared norm: the friction force of a
    // contact sliding with v is -F_n ratio v. Inside the stiction band it is
    // mu_s (3 - x^2) / (2 v_s), x^2 = |v|^2 / v_s^2, smooth at v = 0 (no |v| to differentiate).
    template <class S>
    S coefficient_per_speed(const S& speed_squared) const {
        using std::sqrt;
        using force_support::value_of;
        const S x2 = speed_squared / (stiction_velocity * stiction_velocity);
        if (value_of(x2) <= 1.0) return mu_static * (3.0 - x2) / (2.0 * stiction_velocity);
        const S speed = sqrt(speed_squared);
        return coefficient(speed) / speed;
    }
};

// The normal load of a friction element, from its keys: `normal_force` (N, >= 0; a number or a
// time function: a given load), or `load_joint` (the name of the joint between the element's two
// bodies whose reaction force transverse to the element's axis is the load, solved with the
// multipliers: Force::load_joint, kit reaction_loads.hpp). `what` says what the load is, for the
// message when both are missing.
class NormalLoad {
public:
    NormalLoad(const ForceSpec& spec, const std::string& what) : name_(spec.name) {
        if (spec.params.has("load_joint")) {
            joint_ = spec.params.string("load_joint");
            if (spec.params.has("normal_force"))
                force_support::fail(spec, "give either 'normal_force' or 'load_joint' (the joint whose reaction is the "
                                          "load), not both", &spec.params.at("normal_force"));
            return;
        }
        if (!spec.params.has("normal_force"))
            force_support::fail(spec, "missing key 'normal_force' (" + what +
                                          "), or 'load_joint' (the joint whose reaction is the load)");
        given_ = make_time_function(spec.params.at("normal_force"), "force '" + spec.name + "' normal_force");
        if (given_->evaluate(0.0).f < 0.0)
            force_support::fail(spec, "'normal_force' must not be negative (the load pressing the surfaces together)",
                                &spec.params.at("normal_force"));
    }
    // the joint whose reaction is the load, "" for a given load
    const std::string& joint() const { return joint_; }
    // the given load at t; 0 with a load_joint (its load comes through Force::evaluate_at_load)
    double at(double t) const {
        if (!given_) return 0.0;
        const double n = given_->evaluate(t).f;
        if (n < 0.0)
            throw InputError("force '" + name_ + "'", "force '" + name_ + "': normal_force is negative (" +
                                                          std::to_string(n) + " N) at t = " + std::to_string(t) +
                                                          ": a contact cannot pull; keep the load >= 0");
        return n;
    }

private:
    std::string name_, joint_;
    std::shared_ptr<const TimeFunction> given_;
};

}  // namespace mbd::friction
