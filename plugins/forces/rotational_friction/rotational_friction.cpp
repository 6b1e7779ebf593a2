// Coulomb friction moment between two bodies turning about a common axis: a pin joint's
// friction (pin radius r times the load it carries, book Eq. 5.74 at the pin's surface)
// or a disk clutch (r = 2a/3 for uniform pressure over radius a, Eq. 5.76), plus a preload
// moment (seals, bearing preload) that does not depend on the load.
//
// The axis a is the force's marker axis on body i (planar: the plane normal; spatial: the
// frame's z axis, the scene's `axis`, as for a revolute joint; it turns with body i). The
// relative angular velocity about it is w_r = (omega_i - omega_j) . a, and the moment on i
// is -c(w_r) a (on j +c(w_r) a) with the friction capacity of mbd/sdk/coulomb_law.hpp:
//   c rises to M_s = mu_s r F_n + M_p within the stiction angular velocity, and falls to
//   M_k = mu_k r F_n + M_p while slipping.
// Keys: radius r (m, >= 0), normal_force F_n (N, >= 0, a number or a time function: the
// load the pin or clutch carries), static_friction mu_s, kinetic_friction mu_k
// (0 <= mu_k <= mu_s), preload M_p (N m, >= 0, default 0), stiction_velocity (rad/s, > 0,
// default 1e-6). Not conservative; exact Jacobians.
#include <mbd/sdk/coulomb_law.hpp>
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/time_function.hpp>

#include <memory>
#include <string>

namespace {

using namespace mbd;
using namespace mbd::force_support;

class RotationalFriction final : public LoadedForce<RotationalFriction, 2> {
public:
    explicit RotationalFriction(const ForceSpec& spec)
        : LoadedForce(spec, "two bodies [i, j]"), name_(spec.name) {
        axis_bar_ = marker_or_centre(spec, 0).axis_z();
        radius_ = non_negative(spec, "radius");
        if (!spec.params.has("normal_force"))
            fail(spec, "missing key 'normal_force' (the load the pin or clutch carries, N)");
        normal_ = make_time_function(spec.params.at("normal_force"), "force '" + spec.name + "' normal_force");
        if (normal_->evaluate(0.0).f < 0.0)
            fail(spec, "'normal_force' must not be negative", &spec.params.at("normal_force"));
        mu_s_ = non_negative(spec, "static_friction");
        mu_k_ = non_negative(spec, "kinetic_friction");
        if (mu_k_ > mu_s_)
            fail(spec, "'kinetic_friction' must not exceed 'static_friction'", &spec.params.at("kinetic_friction"));
        preload_ = non_negative_or(spec, "preload", 0.0);
        const double fallback = 1e-6;
        law_.stiction_velocity = number(spec, "stiction_velocity", &fallback);
        if (!(law_.stiction_velocity > 0.0))
            fail(spec, "'stiction_velocity' must be positive (the slip rate below which the joint sticks, rad/s)",
                 &spec.params.at("stiction_velocity"));
    }

    // the friction law at t: static and kinetic moment capacities for the load F_n(t)
    friction::CoulombLaw load(double t) const {
        const double n = normal_->evaluate(t).f;
        if (n < 0.0)
            throw InputError("force '" + name_ + "'", "force '" + name_ + "': normal_force is negative (" +
                                                          std::to_string(n) + " N) at t = " + std::to_string(t));
        friction::CoulombLaw law = law_;
        law.mu_static = mu_s_ * radius_ * n + preload_;
        law.mu_kinetic = mu_k_ * radius_ * n + preload_;
        return law;
    }

    template <class S>
    VX<S> generalized(const PlanarStates<S>& s, const friction::CoulombLaw& law) const {
        const S moment = -law.coefficient(S(s[0].omega - s[1].omega));
        VX<S> Q = VX<S>::Zero(6);
        Q[2] = moment;
        Q[5] = -moment;
        return Q;
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, const friction::CoulombLaw& law) const {
        const V3<S> a = s[0].A * axis_bar_.cast<S>();
        const V3<S> M = -law.coefficient(S((s[0].omega() - s[1].omega()).dot(a))) * a;  // on i, world
        VX<S> Q = VX<S>::Zero(12);
        Q.template segment<3>(3) = s[0].A.transpose() * M;  // moments in body axes
        Q.template segment<3>(9) = -(s[1].A.transpose() * M);
        return Q;
    }

private:
    std::string name_;
    Vec3 axis_bar_;
    double radius_ = 0, mu_s_ = 0, mu_k_ = 0, preload_ = 0;
    std::shared_ptr<const TimeFunction> normal_;
    friction::CoulombLaw law_;
};

std::unique_ptr<Force> make_rotational_friction(const ForceSpec& spec) {
    return std::make_unique<RotationalFriction>(spec);
}

}  // namespace

MBD_FORCE_PLUGIN(rotational_friction, make_rotational_friction)
