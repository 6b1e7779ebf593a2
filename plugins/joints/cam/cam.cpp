// The cam joint plugin (planar; book Sec. 3.4, Eqs. 3.95-3.102, Example 3.8): body i is the
// cam, body j the follower. The profile (cam_profile.hpp) is given in polar form in the joint
// frame on the cam, u_bar(s) = u_m + A_m rho(s), with s the polar angle of the contact point:
// the book's non-generalized surface parameter.
//
// The book writes two equations in (q, s) (Eqs. 3.98-3.100 and Ex. 3.8) and notes that they
// remove one degree of freedom with s. Here s is eliminated inside the joint: for any body
// state it is the stationary point that makes the second equation hold (the foot of the
// perpendicular from the follower point to the profile, or the profile point whose tangent is
// parallel to the follower face), found by Newton from the polar angle of the follower, and the
// joint has ONE row, the normal gap g(q) = 0, whose multiplier is the normal contact force (the
// one multiplier that C_s^T lambda = 0 leaves, book Sec. 8.6, Eq. 8.72). Because the gap is
// stationary in s there (envelope theorem), its Jacobian is that of the gap at fixed s, exactly,
// at any state; gamma uses sdot from differentiating the stationarity condition.
//
// Point followers (knife_edge: r = 0; roller: radius r), P = R_j + A_j u_bar_P:
//   foot point  h(s) = u_bar'(s) . (p_bar - u_bar(s)) = 0,   p_bar = A_i^T (r_P - R_i)
//   g = n . (r_P - r_c) - r,   n = A_i nu_bar(s) (outward unit normal),  r_c = R_i + A_i u_bar(s)
//   J = [ -n^T | -n . A_theta^i u_bar | n^T | n . A_theta^j u_bar_P ]
//   gamma = -( ndot . w + n . (th_i'^2 A_i u_bar - th_j'^2 A_j u_bar_P - th_i' s' A_theta^i u_bar') )
//   with w = rdot_P - (Rdot_i + th_i' A_theta^i u_bar), ndot = th_i' A_theta^i nu_bar + A_i nu_bar' s',
//   s' = -u_bar' . p_bar' / h_s,  h_s = u_bar'' . (p_bar - u_bar) - |u_bar'|^2.
// Flat-faced follower (Ex. 3.8): face through Q (u_bar_Q on j) with unit normal f = A_j f_bar
// pointing from the face into the cam:
//   contact point h(s) = u_bar'(s) . f_c = 0,  f_c = A_i^T f   (tangent parallel to the face)
//   g = f . (r_c - R_j) - f_bar . u_bar_Q
//   J = [ f^T | f . A_theta^i u_bar | -f^T | (A_theta^j f_bar) . (r_c - R_j) ]
//   gamma = -( -th_j'^2 f . D + 2 fdot . Ddot + f . (-th_i'^2 A_i u_bar + 2 th_i' s' A_theta^i u_bar'
//              + s'^2 A_i u_bar'') ),  D = r_c - R_j,  s' = -u_bar' . fdot_c / (u_bar'' . f_c).
// The gap is positive when the bodies separate; the contact pushes while lambda < 0
// (compression_sign), and a run warns where lambda changes sign: a spring-loaded follower
// would lift off there (the joint itself is bilateral and keeps it on the cam).
//
// Scene keys: bodies: [cam, follower]; point (and axis): the profile frame on the cam;
// follower: knife_edge | roller | flat_face; follower_point: [x, y] on the follower, its body
// axes (tip, roller centre, a point of the face); radius: r (roller); face_normal: [x, y]
// (flat_face, follower body axes, towards the cam); profile: {type: eccentric | harmonic |
// spline, ...} (cam_profile.hpp). Profiles must be convex (read_profile refuses one that is not).
#include "cam_profile.hpp"

#include <mbd/sdk/contact_joint.hpp>
#include <mbd/sdk/planar_primitives.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace {

using mbd::Mat2;
using mbd::Vec2;
using mbd::perp;

enum class Follower { KnifeEdge, Roller, FlatFace };

// The profile point in cam body axes at s, with its derivatives and the outward normal.
struct CamPoint {
    Vec2 u, u1, u2;  // u_bar, u_bar', u_bar''
    Vec2 nu, nu1;    // outward unit normal nu_bar and nu_bar'
};

class Cam final : public mbd::ContactJoint {
public:
    Cam(std::unique_ptr<const mbd::cam::Profile> profile, const mbd::Marker& frame, Follower follower,
        const Vec2& follower_point, double radius, const Vec2& face_normal)
        : profile_(std::move(profile)), origin_(frame.u_bar2()), A_m_(mbd::planar_rotation(frame.angle)),
          frame_angle_(frame.angle), follower_(follower), u_P_(follower_point), radius_(radius),
          f_bar_(face_normal) {}

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        mbd::planar::clear(out);
        if (follower_ == Follower::FlatFace)
            flat_face(b.planar(0), b.planar(1), out);
        else
            point_follower(b.planar(0), b.planar(1), out);
    }

private:
    CamPoint at(double s) const {
        const mbd::cam::ProfilePoint p = profile_->point(s);
        CamPoint c{origin_ + A_m_ * p.rho, A_m_ * p.rho1, A_m_ * p.rho2, Vec2::Zero(), Vec2::Zero()};
        const double speed = c.u1.norm();
        const Vec2 tau = c.u1 / speed;
        c.nu = -perp(tau);
        c.nu1 = -perp((c.u2 - tau.dot(c.u2) * tau) / speed);
        return c;
    }

    // Newton on h(s) = 0 from s0; h and h_s from the caller's functions of the profile point.
    template <class H, class Hs>
    double solve(double s, H&& h, Hs&& h_s) const {
        for (int iteration = 0; iteration < 60; ++iteration) {
            const CamPoint c = at(s);
            const double slope = h_s(c);
            if (!(std::abs(slope) > 0.0)) break;
            const double step = h(c) / slope;
            s -= step;
            if (std::abs(step) <= 1e-15 * (1.0 + std::abs(s))) break;
        }
        return s;
    }
    // the polar angle in the profile frame of a direction given in cam body axes
    double polar_angle(const Vec2& direction) const { return std::atan2(direction.y(), direction.x()) - frame_angle_; }

    void point_follower(const mbd::PlanarBody& bi, const mbd::PlanarBody& bj, mbd::ConstraintEval& out) const {
        const Vec2 r_P = bj.point(u_P_), rdot_P = bj.point_velocity(u_P_);
        const Vec2 p = bi.A.transpose() * (r_P - bi.R);
        const Vec2 pdot = bi.A.transpose() * (rdot_P - bi.Rdot) + bi.omega * (bi.A_theta.transpose() * (r_P - bi.R));
        auto h = [&](const CamPoint& c) { return c.u1.dot(p - c.u); };
        auto h_s = [&](const CamPoint& c) { return c.u2.dot(p - c.u) - c.u1.squaredNorm(); };
        const double s = solve(polar_angle(p - origin_), h, h_s);
        const CamPoint c = at(s);
        const double sdot = -c.u1.dot(pdot) / h_s(c);
        const Vec2 n = bi.A * c.nu, r_c = bi.point(c.u);
        const Vec2 w = rdot_P - (bi.Rdot + bi.omega * (bi.A_theta * c.u));
        const Vec2 ndot = bi.omega * (bi.A_theta * c.nu) + sdot * (bi.A * c.nu1);
        mbd::planar::RowSink row(out);
        row.C(0) = n.dot(r_P - r_c) - radius_;
        row.add_J_R(0, 0, -n);
        row.add_J_theta(0, 0, -n.dot(bi.A_theta * c.u));
        row.add_J_R(0, 1, n);
        row.add_J_theta(0, 1, n.dot(bj.A_theta * u_P_));
        row.gamma(0) = -(ndot.dot(w) + n.dot(bi.omega * bi.omega * (bi.A * c.u) - bj.omega * bj.omega * (bj.A * u_P_) -
                                             bi.omega * sdot * (bi.A_theta * c.u1)));
    }

    void flat_face(const mbd::PlanarBody& bi, const mbd::PlanarBody& bj, mbd::ConstraintEval& out) const {
        const Vec2 f = bj.A * f_bar_, fdot = bj.omega * (bj.A_theta * f_bar_);
        const Vec2 f_c = bi.A.transpose() * f;
        const Vec2 fdot_c = (bj.omega - bi.omega) * perp(f_c);
        auto h = [&](const CamPoint& c) { return c.u1.dot(f_c); };
        auto h_s = [&](const CamPoint& c) { return c.u2.dot(f_c); };
        const double s = solve(polar_angle(-f_c), h, h_s);
        const CamPoint c = at(s);
        const double sdot = -c.u1.dot(fdot_c) / h_s(c);
        const Vec2 r_c = bi.point(c.u), D = r_c - bj.R;
        const Vec2 Ddot = bi.Rdot + bi.omega * (bi.A_theta * c.u) + sdot * (bi.A * c.u1) - bj.Rdot;
        mbd::planar::RowSink row(out);
        row.C(0) = f.dot(D) - f_bar_.dot(u_P_);
        row.add_J_R(0, 0, f);
        row.add_J_theta(0, 0, f.dot(bi.A_theta * c.u));
        row.add_J_R(0, 1, -f);
        row.add_J_theta(0, 1, (bj.A_theta * f_bar_).dot(D));
        row.gamma(0) = -(-bj.omega * bj.omega * f.dot(D) + 2.0 * fdot.dot(Ddot) +
                         f.dot(-bi.omega * bi.omega * (bi.A * c.u) + 2.0 * bi.omega * sdot * (bi.A_theta * c.u1) +
                               sdot * sdot * (bi.A * c.u2)));
    }

    std::unique_ptr<const mbd::cam::Profile> profile_;
    Vec2 origin_;
    Mat2 A_m_;
    double frame_angle_;
    Follower follower_;
    Vec2 u_P_;
    double radius_;
    Vec2 f_bar_;
};

std::unique_ptr<mbd::Joint> make_cam(const mbd::JointSpec& spec) {
    const std::string who = mbd::planar::check_contact_spec(
        spec, 2, true, "a spatial cam is the surface contact of book Sec. 8.6", "drives", "against");
    const mbd::Params& p = spec.params;
    const std::string kind = p.string("follower");
    Follower follower;
    if (kind == "knife_edge")
        follower = Follower::KnifeEdge;
    else if (kind == "roller")
        follower = Follower::Roller;
    else if (kind == "flat_face")
        follower = Follower::FlatFace;
    else
        p.at("follower").fail(who + ": unknown follower '" + kind + "' (knife_edge, roller or flat_face)");
    const Vec2 point = p.vector("follower_point", 2);
    double radius = 0.0;
    if (follower == Follower::Roller) radius = p.positive("radius");
    Vec2 normal = Vec2::UnitX();
    if (follower == Follower::FlatFace) {
        normal = p.vector("face_normal", 2);
        if (!(normal.norm() > 0.0)) p.at("face_normal").fail(who + ": 'face_normal' must not be zero");
        normal.normalize();
    }
    return std::make_unique<Cam>(mbd::cam::read_profile(p, who), spec.markers[0], follower, point, radius, normal);
}

}  // namespace

MBD_JOINT_PLUGIN(cam, make_cam)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey cam_keys[] = {
    {"profile", "the cam profile, a map with type: eccentric (radius, eccentricity), harmonic (base, cos, sin) or spline (radii)", nullptr, "{type: harmonic, base: 0.3, cos: [0.03, 0.01], sin: [0, 0.005]}"},
    {"follower", "knife_edge, roller or flat_face", nullptr, "knife_edge"},
    {"follower_point", "[x, y]: the tip, the roller centre or a point of the face, in the follower's body axes", nullptr, "[0.1, 0]"},
    {"radius", "the roller radius (m), > 0; roller followers only", "none: required for a roller", "0.05"},
    {"face_normal", "the face normal in the follower's body axes, towards the cam; flat_face followers only", "none: required for a flat_face", "[0.3, -1]"},
    {}};
}  // namespace

MBD_JOINT_KEYS(cam, "a planar cam (body i) and its follower (body j) in contact", mbd::kTwoBodies, mbd::kPlanarOnly, cam_keys)
