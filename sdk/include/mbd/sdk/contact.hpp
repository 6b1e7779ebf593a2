// Compliant contact between two bodies, for the contact force plugins (sphere_plane,
// sphere_sphere and their planar counterparts circle_line, circle_circle).
//
// A contact is a geometry and two laws:
//  - the geometry (ContactGeometry, from the plugin's shapes at one state): the unit normal n
//    from body i's surface toward body j's, the contact point X and the signed distance
//    (gap) g, negative when the surfaces overlap; the penetration is delta = -g;
//  - the normal law (NormalLaw, Hunt and Crossley's, J. Appl. Mech. 42 (1975) 440):
//      F_n = k delta^n + c delta^n delta_dot     while delta > 0, else 0,
//    clamped at 0 (a contact never pulls: when the damping term would make F_n negative,
//    near the end of a fast separation, it is 0). The damping is c directly, or from a
//    coefficient of restitution e at an impact velocity v_i by a published relation,
//    approximate: Lankarani and Nikravesh (J. Mech. Des. 112 (1990) 369),
//    c = 3 k (1 - e^2) / (4 v_i), or Hunt and Crossley's c = 3 k (1 - e) / (2 v_i);
//  - friction (the regularized Coulomb law of coulomb_law.hpp on the tangential slip
//    velocity v_t of the two bodies' material points at X): F_t = -mu(|v_t|) F_n v_t / |v_t|.
// The force on body j is F = F_n n + F_t at X, on body i -F at X (book Eqs. 5.45-5.46,
// spatial 7.111-7.115: a point force, moments about the mass centres, in body axes).
//
// The gap rate is g_dot = n . (v_j(X) - v_i(X)) with v_k(X) the velocity of body k's
// material point at X: exact for the shapes here, whose X lies on the normal through the
// sphere centres (the terms of the turning normal cancel). So the power of the normal force
// is -F_n delta_dot, and with c = 0 and no friction the element is conservative with the
// potential V = k delta^(n+1) / (n + 1).
#pragma once

#include <mbd/sdk/coulomb_law.hpp>
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <string>

namespace mbd::contact {

using force_support::value_of;

// ------------------------------------------------------------------ the normal law
struct NormalLaw {
    double stiffness = 0.0;  // k, N / m^n
    double exponent = 1.5;   // n (1.5: Hertz, sphere on a plane or on a sphere)
    double damping = 0.0;    // c, N s / m^(n+1)
    double impact_velocity = 0.0;  // the approach speed a restitution was fitted to (0: damping given)

    // F_n of the penetration delta and its rate, >= 0; zero (a constant: no Jacobian) while separated
    template <class S>
    S force(const S& delta, const S& delta_dot) const {
        using std::pow;
        if (value_of(delta) <= 0.0) return S(0.0);
        const S power = pow(delta, exponent);
        const S f = stiffness * power + damping * power * delta_dot;
        return value_of(f) > 0.0 ? f : S(0.0);
    }
    // the elastic energy stored at penetration delta
    double energy(double delta) const {
        return delta > 0.0 ? stiffness * std::pow(delta, exponent + 1.0) / (exponent + 1.0) : 0.0;
    }
};

// The damping of a restitution coefficient e at the impact velocity v_i (both published relations
// are approximate: derived for e near 1 and a short, gravity-free impact).
enum class RestitutionModel { LankaraniNikravesh, HuntCrossley };
inline double damping_from_restitution(RestitutionModel model, double stiffness, double e, double impact_velocity) {
    return model == RestitutionModel::LankaraniNikravesh ? 3.0 * stiffness * (1.0 - e * e) / (4.0 * impact_velocity)
                                                         : 3.0 * stiffness * (1.0 - e) / (2.0 * impact_velocity);
}

// The keys of the normal law: stiffness (> 0), exponent (> 0, default 1.5) and either damping
// (>= 0, default 0) or restitution (0 < e <= 1) with impact_velocity (> 0) and
// restitution_model (lankarani_nikravesh, the default, or hunt_crossley).
inline NormalLaw read_normal_law(const ForceSpec& spec) {
    using namespace force_support;
    NormalLaw law;
    law.stiffness = number(spec, "stiffness");
    if (!(law.stiffness > 0.0))
        fail(spec, "'stiffness' must be positive (k of the contact law F_n = k delta^n + c delta^n delta_dot, N/m^n)",
             &spec.params.at("stiffness"));
    law.exponent = number(spec, "exponent", &law.exponent);
    if (!(law.exponent > 0.0))
        fail(spec, "'exponent' must be positive (n of F_n = k delta^n + ...; 1.5 for Hertz contact of spheres)",
             &spec.params.at("exponent"));
    const bool by_damping = spec.params.has("damping"), by_restitution = spec.params.has("restitution");
    if (by_damping && by_restitution)
        fail(spec, "give either 'damping' or 'restitution' (with 'impact_velocity'), not both",
             &spec.params.at("restitution"));
    if (by_restitution) {
        const double e = number(spec, "restitution");
        if (!(e > 0.0 && e <= 1.0))
            fail(spec, "'restitution' must be in (0, 1] (1: no loss)", &spec.params.at("restitution"));
        if (!spec.params.has("impact_velocity"))
            fail(spec, "'restitution' needs 'impact_velocity' (m/s > 0: the approach speed the damping is fitted to)",
                 &spec.params.at("restitution"));
        const double v = number(spec, "impact_velocity");
        if (!(v > 0.0))
            fail(spec, "'impact_velocity' must be positive (the approach speed, m/s)", &spec.params.at("impact_velocity"));
        const std::string model =
            spec.params.has("restitution_model") ? spec.params.string("restitution_model") : "lankarani_nikravesh";
        if (model != "lankarani_nikravesh" && model != "hunt_crossley")
            fail(spec, "'restitution_model' must be 'lankarani_nikravesh' or 'hunt_crossley', got '" + model + "'",
                 &spec.params.at("restitution_model"));
        law.impact_velocity = v;
        law.damping = damping_from_restitution(
            model == "hunt_crossley" ? RestitutionModel::HuntCrossley : RestitutionModel::LankaraniNikravesh,
            law.stiffness, e, v);
    } else {
        law.damping = non_negative_or(spec, "damping", 0.0);
    }
    return law;
}

// The friction keys: static_friction mu_s (>= 0, default 0: frictionless), kinetic_friction mu_k
// (0 <= mu_k <= mu_s, default mu_s), stiction_velocity v_s (m/s > 0, default 1e-6).
inline friction::CoulombLaw read_friction(const ForceSpec& spec) {
    using namespace force_support;
    friction::CoulombLaw law;
    law.mu_static = non_negative_or(spec, "static_friction", 0.0);
    law.mu_kinetic = non_negative_or(spec, "kinetic_friction", law.mu_static);
    if (law.mu_kinetic > law.mu_static)
        fail(spec, "'kinetic_friction' (" + std::to_string(law.mu_kinetic) + ") must not exceed 'static_friction' (" +
                       std::to_string(law.mu_static) + ")",
             &spec.params.at("kinetic_friction"));
    law.stiction_velocity = number(spec, "stiction_velocity", &law.stiction_velocity);
    if (!(law.stiction_velocity > 0.0))
        fail(spec, "'stiction_velocity' must be positive (the slip speed below which the contact sticks, m/s)",
             &spec.params.at("stiction_velocity"));
    return law;
}

// A length key that must be positive (a radius).
inline double positive_length(const ForceSpec& spec, const std::string& key, const std::string& what) {
    const double v = force_support::number(spec, key);
    if (!(v > 0.0))
        force_support::fail(spec, "'" + key + "' must be positive (" + what + ", m), got " + std::to_string(v),
                            &spec.params.at(key));
    return v;
}

// A unit direction under `key` (D numbers, not zero), e.g. a plane normal in its body's axes.
template <int D>
Eigen::Matrix<double, D, 1> unit_direction(const ForceSpec& spec, const std::string& key, const std::string& what) {
    using namespace force_support;
    if (!spec.params.has(key)) fail(spec, "missing key '" + key + "' (" + what + ")");
    const Eigen::VectorXd v = number_list(spec, key, D, false);
    if (!(v.norm() > 1e-12)) fail(spec, "'" + key + "' must not be the zero vector (" + what + ")", &spec.params.at(key));
    return v.normalized();
}

// ------------------------------------------------------------------ geometry
template <class S, int D>
using Vec = Eigen::Matrix<S, D, 1>;

template <class S, int D>
struct ContactGeometry {
    Vec<S, D> normal;  // unit, from body i toward body j
    Vec<S, D> point;   // X, where the force acts
    S gap;             // signed distance of the surfaces (< 0: overlap)
    bool defined = true;  // false when the shapes give no normal (coincident sphere centres)
};

// A sphere (circle) of radius r centred at C on body j against the plane (line) through P0 with
// unit normal n on body i: g = n . (C - P0) - r, X the foot of the centre on the plane.
template <class S, int D>
ContactGeometry<S, D> sphere_on_plane(const Vec<S, D>& P0, const Vec<S, D>& n, const Vec<S, D>& C, double r) {
    const S height = n.dot(C - P0);
    return {n, Vec<S, D>(C - height * n), S(height - r), true};
}

// Spheres (circles) of radii r_i, r_j centred at C_i, C_j: g = |C_j - C_i| - r_i - r_j, n along
// the line of centres, X the middle of the overlap. Coincident centres give no normal.
template <class S, int D>
ContactGeometry<S, D> sphere_on_sphere(const Vec<S, D>& Ci, double ri, const Vec<S, D>& Cj, double rj) {
    using std::sqrt;
    const Vec<S, D> d = Cj - Ci;
    const S d2 = d.squaredNorm();
    if (value_of(d2) < 1e-24 * (ri + rj) * (ri + rj)) return {Vec<S, D>::Zero(), Ci, S(-ri - rj), false};
    const S distance = sqrt(d2);
    const Vec<S, D> n = d / distance;
    const S gap = distance - ri - rj;
    return {n, Vec<S, D>(Ci + (ri + 0.5 * gap) * n), gap, true};
}

// ------------------------------------------------------------------ kinematics of a body at X
template <class S>
Vec<S, 2> material_velocity(const force_support::PlanarT<S>& b, const Vec<S, 2>& X) {
    const Vec<S, 2> r = X - b.R;
    return b.Rdot + b.omega * Vec<S, 2>(-r.y(), r.x());
}
template <class S>
Vec<S, 3> material_velocity(const force_support::SpatialT<S>& b, const Vec<S, 3>& X) {
    return b.Rdot + b.omega().cross(X - b.R);
}
// The generalized force of F at X on body b (book Eqs. 5.45-5.46; spatial 7.111-7.115, moment in body axes).
template <class S, class Out>
void add_point_force(const force_support::PlanarT<S>& b, const Vec<S, 2>& X, const Vec<S, 2>& F, Out&& Q) {
    const Vec<S, 2> r = X - b.R;
    Q.template head<2>() += F;
    Q[2] += r.x() * F.y() - r.y() * F.x();
}
template <class S, class Out>
void add_point_force(const force_support::SpatialT<S>& b, const Vec<S, 3>& X, const Vec<S, 3>& F, Out&& Q) {
    Q.template head<3>() += F;
    Q.template tail<3>() += b.A.transpose() * Vec<S, 3>((X - b.R).cross(F));
}

// The gap and its rate at one state: what an event function of the contact watches.
struct GapAndRate {
    double gap = 0.0;   // signed distance, m (< 0: penetration)
    double rate = 0.0;  // d gap / dt, m/s
};

// ------------------------------------------------------------------ the element
// A two-body contact force: Derived gives `geometry(states)` (templated on the states type,
// returning ContactGeometry<S, D> for the D of its dimension). Q, exact Jacobians, the gap and
// its rate, the potential and conservativeness come from here.
template <class Derived>
class ContactForce : public force_support::LoadedForce<Derived, 2> {
public:
    // accepted: the dimension of this type; other: the type to use in a scene of the other dimension
    ContactForce(const ForceSpec& spec, Dimension accepted, const std::string& other)
        : force_support::LoadedForce<Derived, 2>(spec, "two bodies [i, j]") {
        if (spec.dimension != accepted)
            force_support::fail(spec, "'" + spec.type + "' is a " + to_string(accepted) + " contact; in a " +
                                          to_string(spec.dimension) + " scene use '" + other + "'");
        normal_ = read_normal_law(spec);
        friction_ = read_friction(spec);
    }

    int load(double) const { return 0; }  // no time-dependent input

    template <class S>
    force_support::VX<S> generalized(const force_support::PlanarStates<S>& s, int) const {
        return contact_force<S>(s);
    }
    template <class S>
    force_support::VX<S> generalized(const force_support::SpatialStates<S>& s, int) const {
        return contact_force<S>(s);
    }

    GapAndRate gap_and_rate(const BodyStates& b) const {
        if (!b.planar_bodies.empty()) return gap_and_rate_of(force_support::planar_states<double>(b));
        return gap_and_rate_of(force_support::spatial_states<double>(b));
    }
    double potential_energy(const BodyStates& b) const override { return normal_.energy(-gap_and_rate(b).gap); }
    CompliantLaw compliant_law() const override {
        return {normal_.stiffness, normal_.exponent, normal_.impact_velocity};
    }

    // --- the event: the gap, so that no step straddles the onset of the contact force (its
    // kink at gap = 0); compliant, the state is not changed there, and a resting contact is
    // held by the normal law.
    int event_count() const override { return 1; }
    std::string event_name(int) const override { return "contact"; }
    void event_values(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> g) const override { g[0] = gap_and_rate(b).gap; }
    EventImpact event_impact(int, const BodyStates& b, Eigen::Ref<Eigen::VectorXd> G) const override {
        // the gap's rate is linear in the velocities at given positions: entry k of G = dgdot/dv
        // is the rate with velocity k at one and the others at zero
        BodyStates probe = b;
        if (!b.planar_bodies.empty()) {
            PlanarBody copy[2] = {b.planar(0), b.planar(1)};
            probe.planar_bodies = {&copy[0], &copy[1]};
            for (int k = 0; k < 6; ++k) {
                for (PlanarBody& body : copy) body.Rdot.setZero(), body.omega = 0.0;
                PlanarBody& moved = copy[k / 3];
                if (k % 3 < 2) moved.Rdot[k % 3] = 1.0; else moved.omega = 1.0;
                G[k] = gap_and_rate(probe).rate;
            }
        } else {
            SpatialBody copy[2] = {b.spatial(0), b.spatial(1)};
            probe.spatial_bodies = {&copy[0], &copy[1]};
            for (int k = 0; k < 12; ++k) {
                for (SpatialBody& body : copy) body.Rdot.setZero(), body.omega_bar.setZero();
                SpatialBody& moved = copy[k / 6];
                if (k % 6 < 3) moved.Rdot[k % 6] = 1.0; else moved.omega_bar[k % 6 - 3] = 1.0;
                G[k] = gap_and_rate(probe).rate;
            }
        }
        EventImpact onset;
        onset.holds_resting = true;
        return onset;
    }
    bool is_conservative() const override { return normal_.damping == 0.0 && friction_.mu_static == 0.0; }

    const NormalLaw& normal_law() const { return normal_; }
    const friction::CoulombLaw& friction_law() const { return friction_; }

protected:
    // Refuses a scene whose shapes overlap at t = 0 by more than `radius` (the sphere's, the
    // smaller of two): the normal law models a small local deformation (Hertz: delta much
    // below the radius), and a centre already past the other surface would be thrown out at a
    // speed nothing in the scene means. Each geometry calls it once its shapes are read.
    void refuse_deep_start(const ForceSpec& spec, double radius, const std::string& what) const {
        BodyStates b;
        PlanarBody planar[2];
        SpatialBody spatial[2];
        for (int k = 0; k < 2; ++k) {
            const BodyInfo& body = spec.bodies[k];
            if (spec.dimension == Dimension::Planar) {
                planar[k].set(body.position.head<2>(), body.angle, Vec2::Zero(), 0.0);
                b.planar_bodies.push_back(&planar[k]);
            } else {
                spatial[k].R = body.position;
                spatial[k].A = body.orientation;
                b.spatial_bodies.push_back(&spatial[k]);
            }
        }
        const double depth = -gap_and_rate(b).gap;
        if (depth > radius)
            force_support::fail(spec, "the shapes overlap by " + format_number(depth) + " m at t = 0, more than " +
                                          what + " " + format_number(radius) + " m: the compliant law holds for a "
                                          "small overlap and would throw the bodies apart; place them touching or "
                                          "apart (an initial overlap may be at most " + what + ")");
    }

private:
    const Derived& self() const { return static_cast<const Derived&>(*this); }
    template <class S, class States>
    force_support::VX<S> contact_force(const States& s) const;
    template <class States>
    GapAndRate gap_and_rate_of(const States& s) const {
        const auto g = self().geometry(s);
        if (!g.defined) return {g.gap, 0.0};
        return {g.gap, g.normal.dot(material_velocity(s[1], g.point) - material_velocity(s[0], g.point))};
    }

    NormalLaw normal_;
    friction::CoulombLaw friction_;
};

template <class Derived>
template <class S, class States>
force_support::VX<S> ContactForce<Derived>::contact_force(const States& s) const {
    const auto g = self().geometry(s);
    constexpr int D = decltype(g.normal)::RowsAtCompileTime;
    constexpr int nv = D == 2 ? 3 : 6;
    force_support::VX<S> Q = force_support::VX<S>::Zero(2 * nv);
    if (!g.defined || value_of(g.gap) >= 0.0) return Q;  // separated: no force, no Jacobian
    const Vec<S, D> v_rel = material_velocity(s[1], g.point) - material_velocity(s[0], g.point);
    const S gap_rate = g.normal.dot(v_rel);
    const S Fn = normal_.force(S(-g.gap), S(-gap_rate));
    if (value_of(Fn) == 0.0) return Q;
    Vec<S, D> F = Fn * g.normal;  // on j
    if (friction_.mu_static > 0.0) {
        const Vec<S, D> v_t = v_rel - gap_rate * g.normal;
        F -= Fn * friction_.coefficient_per_speed(S(v_t.squaredNorm())) * v_t;
    }
    add_point_force(s[1], g.point, F, Q.template segment<nv>(nv));
    add_point_force(s[0], g.point, Vec<S, D>(-F), Q.template segment<nv>(0));
    return Q;
}

}  // namespace mbd::contact
