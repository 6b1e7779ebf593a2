// The recursive path's right-hand side for planar trees in planar algebra (issue 13: the
// 5-link chain's rhs against a hand-written floor, bench/rhs_floor.cpp).
//
// ArticulatedBody (articulated_body.hpp) runs planar scenes through the spatial algorithm
// embedded in 3-D: 6-vectors, 6 x 6 articulated inertias, rotation matrices per freedom.
// In the plane every motion vector is (vx, vy, omega) at a body's centre of mass, world
// axes, and the same recursion shrinks to
//   transfer  Phi = [I2 d; 0 1],  d = k x (R_c - R_p)        (rigid motion of the parent)
//   pin       H column = sigma [k x (R_c - o); 1]            (o the joint point, sigma = +-1 the axis)
//   slider    H column = [a; 0]                               (a the world axis)
//   bias      a = [oddot + ...; 0]: no gyroscopic term; angular velocity-product terms vanish
// with P = diag(m, m, J) and the articulated-body sweeps of articulated_body.hpp on 3 x 3
// blocks (scalar D for a 1-DOF joint). The absolute angles add: no trigonometry but one
// sine and cosine per body.
//
// Only rhs() takes this path; the state conversions, reactions and accelerations at a
// State stay on the spatial algorithm, which is therefore the oracle of the planar one
// (tests/test_embedding.cpp compares them on every planar tree scene). A tree with a
// freedom that is not planar (a revolute axis off z, a slider axis with a z component)
// keeps the spatial rhs. A driven (prescribed) pin or slider passes its whole articulated
// inertia to its parent, as in articulated_body.hpp.
#pragma once

#include "articulated_body.hpp"

#include <vector>

namespace mbd::articulated {

class PlanarArticulatedBody final : public ArticulatedBody {
public:
    void bind(System& system, const FormulationOptions& options) override;
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override;
    // whether rhs() runs in planar algebra (false: the spatial algorithm)
    bool planar_algebra() const { return fast_; }

private:
    using Mat3X = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3>;
    using Mat33 = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
    using Vec3X = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;
    struct Link {  // one edge of edges_ (same order) and its child body
        int parent = -1;         // index of the parent's link, -1: the ground
        double x = 0, y = 0, theta = 0;
        double cos_theta = 1, sin_theta = 0;  // of theta, once per kinematics (its children use them)
        Vec3 v = Vec3::Zero();   // (vx, vy, omega)
        Vec2 d = Vec2::Zero();   // Phi = [I2 d; 0 1]
        Vec3 a = Vec3::Zero();   // velocity-product acceleration (vdot at vdot_p = 0, udot = 0)
        Mat3X H, U;              // 3 x nu: partial velocities, P H
        Mat33 Dinv;              // (H^T P H)^-1
        Mat3 P = Mat3::Zero();
        Vec3 z = Vec3::Zero();
        Vec3 vdot = Vec3::Zero();
    };
    // at s_, u_
    void planar_kinematics();
    // udot_ at the kinematics and Q_
    void planar_articulated(double t);
    [[noreturn]] void singular(double t, int body) const;

    bool fast_ = false;
    std::vector<Link> links_;
    std::vector<int> link_of_body_;
};

}  // namespace mbd::articulated
