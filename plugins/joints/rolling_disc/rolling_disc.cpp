// Rolling disc: a thin disc of radius r on body j rolls without slipping on a plane fixed
// on body i (usually the ground). Spatial only.
//
// Geometry (world axes): disc centre c = R_j + A_j u_bar_c and wheel axis a = A_j a_bar (the
// joint marker on body j: its origin and z axis); plane point P = R_i + A_i u_bar_P with
// normal n = A_i n_bar. The contact point is the rim point lowest along n,
//     r_C = c + r d,   d = -(n - mu a) / s,   mu = n . a,   s = |n - mu a| = sqrt(1 - mu^2),
// and the rolling and lateral directions of the contact are t1 = a x n / s, t2 = n x t1.
// Rows, with w = V_j(r_C) - V_i(r_C) the slip velocity (the velocities of the material
// points of the two bodies at r_C, V_k(x) = Rdot_k + omega_k x (x - R_k)):
//   holonomic     C = n . (r_C - P)                     the rim's height above the plane
//   velocity      t1 . w = 0,  t2 . w = 0               no slip (A v = b with b = 0)
// The spin about the normal is free (a point contact, as in the Whipple bicycle).
//
// One formula gives all three rows. Because r_C is the lowest rim point, moving it along the
// rim does not change the height to first order (envelope), so Cdot = n . w and, for each
// direction e in {n, t1, t2}, the row is e . w = e^T (G_j - G_i) v with G_k the point Jacobian
// of body k at r_C (3 x 6: [I, -skew(r_C - R_k) A_k], book Eq. 7.128's virtual rotation in
// body axes). Differentiating e . w along a motion,
//   d/dt V_k(r_C) = G_k vdot_k + omega_k x (rdot_C - Rdot_k)   (omega_dot_k = A_k wbar_dot_k),
// so that d/dt (e . w) = e^T (G_j - G_i) vdot - gamma_e with
//   gamma_e = -(edot . w + e . [omega_j x (rdot_C - Rdot_j) - omega_i x (rdot_C - Rdot_i)]),
// the holonomic row's gamma (book Eq. 3.124) and the velocity rows' (joint.hpp) alike.
// rdot_C and edot follow from ndot = omega_i x n, adot = omega_j x a by the chain rule.
//
// Scene keys (docs/scene-format.md): point = the disc centre and axis = the wheel axis (core
// keys, world at t = 0); radius (> 0); normal (the plane's normal, world at t = 0, default
// [0, 0, 1]); plane_point (a point of the plane, world at t = 0, default: the disc's lowest
// rim point at t = 0, so that the scene starts in contact).
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>
#include <mbd/sdk/rotation.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace {

using mbd::Mat3;
using mbd::Vec3;

// The contact of the disc with the plane and its rate along the current motion.
struct Contact {
    Vec3 n, ndot;          // plane normal
    Vec3 point, rate;      // r_C and its geometric rate rdot_C
    Vec3 t1, t1dot, t2, t2dot;
};

class RollingDisc final : public mbd::Joint {
public:
    RollingDisc(const Vec3& centre, const Vec3& axis, double radius, const Vec3& normal, const Vec3& plane_point)
        : centre_(centre), axis_(axis), radius_(radius), normal_(normal), plane_point_(plane_point) {}

    int rows() const override { return 1; }
    int velocity_rows() const override { return 2; }
    std::string row_name(int) const override { return "contact height"; }
    std::string velocity_row_name(int row) const override {
        return row == 0 ? "no-slip rolling direction" : "no-slip lateral";
    }

    void evaluate(const mbd::BodyStates& bodies, mbd::ConstraintEval& out) const override {
        const mbd::SpatialBody& bi = bodies.spatial(0);
        const Contact k = contact(bodies);
        out.C[0] = k.n.dot(k.point - bi.point(plane_point_));
        write_row(bodies, k, k.n, k.ndot, out.J.row(0), out.gamma[0]);
    }

    void evaluate_velocity(const mbd::BodyStates& bodies, mbd::VelocityConstraintEval& out) const override {
        const Contact k = contact(bodies);
        write_row(bodies, k, k.t1, k.t1dot, out.A.row(0), out.gamma[0]);
        write_row(bodies, k, k.t2, k.t2dot, out.A.row(1), out.gamma[1]);
        out.b.setZero();  // rolling without slip: no prescribed slip velocity
    }

private:
    Contact contact(const mbd::BodyStates& bodies) const {
        const mbd::SpatialBody& bi = bodies.spatial(0);
        const mbd::SpatialBody& bj = bodies.spatial(1);
        const Vec3 wi = bi.omega(), wj = bj.omega();
        Contact k;
        k.n = bi.A * normal_;
        k.ndot = wi.cross(k.n);
        const Vec3 a = bj.A * axis_, adot = wj.cross(a);
        const double mu = k.n.dot(a), mudot = k.ndot.dot(a) + k.n.dot(adot);
        const double s = std::sqrt(1.0 - mu * mu), sdot = -mu * mudot / s;
        const Vec3 d = -(k.n - mu * a) / s;
        const Vec3 ddot = -(k.ndot - mudot * a - mu * adot) / s - d * (sdot / s);
        const Vec3 c = bj.point(centre_), cdot = bj.point_velocity(centre_);
        k.point = c + radius_ * d;
        k.rate = cdot + radius_ * ddot;
        k.t1 = a.cross(k.n) / s;
        k.t1dot = (adot.cross(k.n) + a.cross(k.ndot)) / s - k.t1 * (sdot / s);
        k.t2 = k.n.cross(k.t1);
        k.t2dot = k.ndot.cross(k.t1) + k.n.cross(k.t1dot);
        return k;
    }

    // The row e . w: its 12 coefficients e^T [-G_i, G_j] and gamma_e (see the header).
    template <class Row>
    static void write_row(const mbd::BodyStates& bodies, const Contact& k, const Vec3& e, const Vec3& edot, Row row,
                          double& gamma) {
        Vec3 slip = Vec3::Zero(), quadratic = Vec3::Zero();
        for (int b = 0; b < 2; ++b) {
            const mbd::SpatialBody& body = bodies.spatial(b);
            const double sign = b == 0 ? -1.0 : 1.0;
            const Vec3 arm = k.point - body.R;
            const Vec3 w = body.omega();
            row.template segment<3>(6 * b) = sign * e.transpose();
            // e^T (-skew(arm) A) = (A^T (arm x e))^T
            row.template segment<3>(6 * b + 3) = sign * (body.A.transpose() * arm.cross(e)).transpose();
            slip += sign * (body.Rdot + w.cross(arm));
            quadratic += sign * w.cross(k.rate - body.Rdot);
        }
        gamma = -(edot.dot(slip) + e.dot(quadratic));
    }

    Vec3 centre_, axis_;      // on body j
    double radius_;
    Vec3 normal_, plane_point_;  // on body i
};

Vec3 world_vector(const mbd::JointSpec& spec, const std::string& key, const std::string& who) {
    return spec.params.at(key).as_vector(key, 3, who);
}

std::unique_ptr<mbd::Joint> make_rolling_disc(const mbd::JointSpec& spec) {
    const std::string who = "joint '" + spec.name + "'";
    mbd::spatial::require_spatial_pair(spec,
                              "a disc rolling on a plane leans, steers and rolls in three dimensions: use a spatial "
                              "scene (dimension: spatial), or in a planar scene a 'rack_pinion' joint for a wheel "
                              "rolling on a line",
                              "[plane, disc]");
    const double radius = spec.params.positive("radius");
    Vec3 normal = Vec3::UnitZ();
    if (spec.params.has("normal")) {
        normal = world_vector(spec, "normal", who);
        if (!(normal.norm() > 0.0)) spec.params.at("normal").fail(who + ": 'normal' must be a non-zero vector");
        normal.normalize();
    }
    // the disc's frame at t = 0 in world: the marker on body j
    const mbd::BodyInfo& plane_body = spec.bodies[0];
    const mbd::BodyInfo& disc_body = spec.bodies[1];
    const mbd::Marker& disc = spec.markers[1];
    const Vec3 centre0 = disc_body.position + disc_body.orientation * disc.u_bar;
    const Vec3 axis0 = disc_body.orientation * disc.axis_z();
    const Vec3 in_plane = normal - normal.dot(axis0) * axis0;
    if (in_plane.norm() < 1e-9)
        spec.params.fail("the wheel axis is along the plane normal at t = 0: the disc lies flat on the plane and has "
                         "no single contact point; tilt 'axis' away from 'normal'");
    Vec3 plane_point = centre0 - radius * in_plane.normalized();  // the lowest rim point
    if (spec.params.has("plane_point")) plane_point = world_vector(spec, "plane_point", who);
    // into the bodies' own axes (the ground's pose is the identity)
    const Mat3 Ai = plane_body.orientation;
    return std::make_unique<RollingDisc>(disc.u_bar, disc.axis_z(), radius, Ai.transpose() * normal,
                                         Ai.transpose() * (plane_point - plane_body.position));
}

}  // namespace

MBD_JOINT_PLUGIN(rolling_disc, make_rolling_disc)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey rolling_disc_keys[] = {
    {"radius", "the disc radius (m), > 0", nullptr, "0.3"},
    {"normal", "the plane's normal, world at t = 0, non-zero", "[0, 0, 1]", "[0, 0.2, 1]"},
    {"plane_point", "a point of the plane, world at t = 0", "the disc's lowest rim point at t = 0", "[0, 0, -0.1]"},
    {}};
}  // namespace

MBD_JOINT_KEYS(rolling_disc, "a thin disc on body j rolling without slip on a plane of body i", mbd::kTwoBodies, mbd::kSpatialOnly, rolling_disc_keys)
