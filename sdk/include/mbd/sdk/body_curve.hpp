// A flexible body whose material points along one parameter s form a curve: the centre line of
// a beam (the ANCF cables and beams, plugins/bodies/ancf, where s is the arc length of the
// straight reference configuration). A joint whose point moves along the body (the core's
// `beam_slider`, docs/scene-format.md) evaluates the curve at a varying s with its
// s-derivatives, where a material frame (body.hpp) is fixed at one s.
//
// At parameter s the material point is at r(q, s), with
//     velocity      rdot = S(q, s) v                (S the 3 x n Jacobian of body.hpp's point())
//     acceleration  rddot = S(q, s) vdot + bias      (bias = Sdot v; zero for ANCF, S = S(s))
// and the s-derivatives r_s, r_ss, rdot_s = S_s v that a point sliding along the curve needs.
//
// The core finds the interface by dynamic_cast from the body's FlexibleBody, so a body type that
// does not implement it is unchanged (a slider on it is refused by name when the scene is read).
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>  // MBD_SDK_API

#include <Eigen/Core>

namespace mbd {

// The curve at one parameter, world axes (planar bodies: z = 0).
struct CurvePoint {
    Vec3 r = Vec3::Zero();       // position
    Vec3 r_s = Vec3::Zero();     // dr/ds (the tangent, not normalised)
    Vec3 r_ss = Vec3::Zero();    // d2r/ds2
    Vec3 rdot = Vec3::Zero();    // velocity of the material point at s
    Vec3 rdot_s = Vec3::Zero();  // its s-derivative
    Vec3 bias = Vec3::Zero();    // acceleration at fixed s minus S vdot
    // for a joint that also follows the tangent's direction (a sleeve):
    Vec3 r_sss = Vec3::Zero();   // d3r/ds3
    Vec3 rdot_ss = Vec3::Zero(); // d2(rdot)/ds2
    Vec3 bias_s = Vec3::Zero();  // the s-derivative of bias (zero for ANCF)
};

class MBD_SDK_API BodyCurve {
public:
    virtual ~BodyCurve() = default;

    // The parameter range [curve_break(0), curve_break(curve_pieces())], cut into pieces on each
    // of which the curve is smooth (an element each: r_ss may jump between them). A joint
    // searches them for the closest point.
    virtual int curve_pieces() const = 0;
    virtual double curve_break(int k) const = 0;

    // The curve at s. s may lie a little outside the range: the end pieces are continued, so that
    // a joint can tell by how much a point left the body.
    virtual void curve_point(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double s, CurvePoint& out) const = 0;

    // J(row, :) += w^T S(q, s): the row of a constraint w . r(q, s) over the body's velocities.
    virtual void add_curve_jacobian(const Eigen::VectorXd& q, double s, const Vec3& w, Eigen::Ref<Eigen::MatrixXd> J,
                                    int row) const = 0;
    // J(row, :) += w^T S_s(q, s): the row of w . r_s(q, s), r_s's rate being S_s v + (its part of bias_s).
    virtual void add_curve_slope_jacobian(const Eigen::VectorXd& q, double s, const Vec3& w,
                                          Eigen::Ref<Eigen::MatrixXd> J, int row) const = 0;
};

}  // namespace mbd
