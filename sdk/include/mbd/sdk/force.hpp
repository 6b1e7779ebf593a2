// The force interface: what every force plugin implements.
//
// A force element adds generalized forces Q (book Eq. 5.49, delta W = Q^T delta q)
// to the velocity rows of the bodies it touches, in the element's body order,
// one block of velocities_per_body entries per body. For spatial bodies the
// rotational entries are moments in body axes (conjugate to dpi_bar).
// Forces that can supply them also give the Jacobians dQ/dq (with respect to
// the velocity-like position increments, as for joints) and dQ/dv, used by
// implicit integrators and by statics.
//
// Events (unilateral stops and contacts, docs/plugin-sdk.md "Events"): an element may
// declare event functions g_i of its bodies' positions, g_i >= 0 while its gap is open.
// A sign change of g_i is an event: the integrators that locate events (dopri5, dop853, cvode)
// end a step exactly there, so no step straddles a gap closing or opening. At a closing
// (g_i turning negative) the element's EventImpact says what happens: nothing but the end
// of the step (the onset of a compliant force), or an impact with Newton's law of
// restitution that the core applies on the constrained system.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mbd {

// What a gap closing (g_i turning negative) means, for one event of an element.
struct EventImpact {
    // True: an impact with Newton's law, gdot+ = -restitution * gdot- (gdot = G v), by an
    // impulse along G^T on the constrained system. False: only a kink of the element's own
    // force (a compliant contact's onset); the state is unchanged.
    bool impact = false;
    double restitution = 0.0;  // e in [0, 1]
    // An impact whose rebound speed e |gdot-| is below rest_velocity ends at rest on the stop
    // (a plastic impulse, gdot+ = 0), not in a rebound: rebounds of ever smaller height would
    // otherwise follow one another without end.
    double rest_velocity = 0.0;
    // The element's force holds a resting contact (a compliant law acting while g_i < 0); an
    // element without one cannot rest, and a run that comes to rest on it stops with an error.
    bool holds_resting = false;
};

// The compliant normal law F_n = k delta^n (+ damping) an element holds between its two bodies
// (mbd/sdk/contact.hpp), for the automatic choice (docs/user-guide.md "The automatic choice"): it
// resolves the penetration the law holds and counts its frequency. stiffness 0: none.
struct CompliantLaw {
    double stiffness = 0.0;        // k, N/m^n
    double exponent = 1.0;         // n
    double impact_velocity = 0.0;  // the approach speed the damping was fitted to (0: not given)
};

struct ForceSpec {
    std::string name;
    std::string type;
    Dimension dimension = Dimension::Planar;
    std::vector<BodyInfo> bodies;   // the bodies the force acts on (gravity: all bodies)
    std::vector<Marker> markers;    // application frames, one per body when the force has points
    Vec3 gravity = Vec3::Zero();    // the scene's gravity vector (planar: z = 0)
    Params params;                  // keys not consumed by the core
};

class MBD_SDK_API Force {
public:
    virtual ~Force() = default;

    // Add this element's generalized force to Q (size velocities_per_body * bodies).
    virtual void evaluate(const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> Q) const = 0;

    // Jacobians of Q: dQ/dq (position increments) and dQ/dv, both square, added into.
    virtual bool has_jacobians() const { return false; }
    virtual void jacobians(const BodyStates& /*bodies*/, Eigen::Ref<Eigen::MatrixXd> /*dQ_dq*/,
                           Eigen::Ref<Eigen::MatrixXd> /*dQ_dv*/) const {}

    // Potential energy of the conservative part (gravity, spring stiffness); the
    // non-conservative part (damping, actuation) is not included.
    virtual double potential_energy(const BodyStates& /*bodies*/) const { return 0.0; }
    // True when Q = -dV/dq exactly (no damping, no time-dependent actuation).
    virtual bool is_conservative() const { return false; }

    // --- a load from a joint's reaction (docs/plugin-sdk.md "Loads from joint reactions")
    // The name of the joint whose reaction presses this element's surfaces together, or "" (the
    // default): friction in a pin or a guide. The element's load N is then the magnitude of that
    // joint's reaction force transverse to load_axis() (a pin's radial load, a guide's normal
    // reaction), which a formulation that supports such loads solves together with the
    // multipliers (Formulation::supports_reaction_loads); the host refuses the others by name.
    virtual std::string load_joint() const { return std::string(); }
    // The unit axis the load is transverse to, world axes (the contact line, the pin's axis).
    virtual Vec3 load_axis(const BodyStates& /*bodies*/) const { return Vec3::Zero(); }
    // Q at load N, added into; it must be affine in N. For an element with a load_joint(),
    // evaluate() and jacobians() are this at N = 0.
    virtual void evaluate_at_load(const BodyStates& bodies, double /*load*/, Eigen::Ref<Eigen::VectorXd> Q) const {
        evaluate(bodies, Q);
    }
    // Dry friction: the diagnostics integrate -Q^T v of these elements as the energy friction
    // dissipated (docs/formulations.md "Diagnostics").
    virtual bool is_friction() const { return false; }
    // A compliant contact between the element's two bodies (the first two of its bodies):
    // its normal law; the default (stiffness 0) is none.
    virtual CompliantLaw compliant_law() const { return {}; }

    // --- events (none by default)
    virtual int event_count() const { return 0; }
    // "lower", "upper": for messages and the run's event list.
    virtual std::string event_name(int /*event*/) const { return std::string(); }
    // g (size event_count()), functions of the positions only, >= 0 while open.
    virtual void event_values(const BodyStates& /*bodies*/, Eigen::Ref<Eigen::VectorXd> /*g*/) const {}
    // For event `event`: G = dg/dv (gdot = G v; velocities_per_body * bodies entries, written, not
    // added) and what its closing means.
    virtual EventImpact event_impact(int /*event*/, const BodyStates& /*bodies*/,
                                     Eigen::Ref<Eigen::VectorXd> /*G*/) const {
        return {};
    }
};

}  // namespace mbd
