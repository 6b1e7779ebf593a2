// A joint one of whose bodies is a curve: a flexible body that implements BodyCurve (sdk
// body_curve.hpp), along which the joint's point moves (the `beam_slider`, beam_slider.hpp).
// Where a joint at a flexible body ordinarily sees the material frame at fixed parameters as a
// rigid body (sdk body.hpp, J = J_f G), such a joint is handed the body's curve, coordinates and
// velocities, and writes its rows' block over the body's velocities itself
// (ConstraintSystem::evaluate_joint). Core-internal: the scene makes it by its type.
#pragma once

#include <mbd/sdk/body_curve.hpp>
#include <mbd/sdk/domain_error.hpp>
#include <mbd/sdk/joint.hpp>

#include <Eigen/Core>

namespace mbd {

class CurveJoint : public Joint {
public:
    // The slot of the joint's bodies that holds the curve (a flexible attachment there).
    static constexpr int kCurveSlot = 0;

    // The rows at these bodies' states (the curve's slot holds the ground) and the curve at the
    // body's q and v: out as Joint::evaluate (the curve slot's columns left zero) and J_curve
    // (rows x n, zeroed by the caller) the rows' Jacobian over the curve body's velocities.
    virtual void evaluate_on_curve(const BodyStates& bodies, const BodyCurve& curve, const Eigen::VectorXd& q,
                                   const Eigen::VectorXd& v, ConstraintEval& out,
                                   Eigen::Ref<Eigen::MatrixXd> J_curve) const = 0;

    // Where the joint acts on the curve, for its reaction there (reactions.hpp): a frame at the
    // curve's point (origin R, axes A, world) and the rows' Jacobian J_frame (rows x 3 planar
    // [Rdot, omega], rows x 6 spatial [Rdot, wbar]) over that frame's velocities, so that the
    // reaction on the body there is -J_frame^T lambda.
    virtual void curve_frame(const BodyStates& bodies, const BodyCurve& curve, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& v, Mat3& A, Vec3& R, Eigen::MatrixXd& J_frame) const = 0;

    // Without its curve the rows do not exist; the core always calls evaluate_on_curve.
    void evaluate(const BodyStates& /*bodies*/, ConstraintEval& /*out*/) const override {
        throw DomainError("this joint is evaluated on its flexible body's centre line only");
    }
};

}  // namespace mbd
