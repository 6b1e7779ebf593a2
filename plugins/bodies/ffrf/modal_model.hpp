// What a planar floating-frame-of-reference (FFRF) body knows about its deformation: the inertia
// shape integrals of its modes and their stiffness, and the modes at its material points.
//
// A material point at u0 (body axes, undeformed) is displaced by S(u0) p, p the m modal
// coordinates, S the 2 x m mode shapes; its position is r = R + A(theta) (u0 + S p)
// (Shabana, Dynamics of Multibody Systems, Ch. 5 "Floating frame of reference formulation",
// the kinematic description r = R + A(u0 + uf), uf = S qf). With P = [0 -1; 1 0] (dA/dtheta = A P),
// the kinetic energy over the mass rho dV needs only these integrals (the "inertia shape
// integrals" of the same chapter), computed here once:
//     m      = int rho                  S0   = int rho u0          (2)
//     Sbar   = int rho S       (2 x m)  I00  = int rho u0.u0
//     I0f    = int rho u0^T S  (1 x m)  I0Pf = int rho (P u0)^T S  (1 x m)
//     Mff    = int rho S^T S   (m x m)  Stil = int rho S^T P S     (m x m, skew)
// plus the modal stiffness Kff (strain energy p^T Kff p / 2) and, for the geometric (centrifugal)
// stiffening of a beam clamped at the frame's origin along its x axis (ffrf_body.cpp), the matrix
//     Kg = int rho A (L^2 - x^2) / 2  phi' phi'^T dx.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace mbd::ffrf {

using Matrix2X = Eigen::Matrix<double, 2, Eigen::Dynamic>;

// The modes at one material point: undeformed position u0, mode shapes S (2 x m) and the small
// rotation of the material frame per mode (1 x m: the frame turns by rotation . p).
struct ModalPoint {
    Eigen::Vector2d u0 = Eigen::Vector2d::Zero();
    Matrix2X S;
    Eigen::RowVectorXd rotation;
};

struct ModalModel {
    int modes = 0;
    double mass = 0.0, I00 = 0.0;
    Eigen::Vector2d S0 = Eigen::Vector2d::Zero();
    Matrix2X Sbar;
    Eigen::RowVectorXd I0f, I0Pf;
    Eigen::MatrixXd Mff, Stilde, Kff;
    Eigen::MatrixXd Kg;  // empty when the modes cannot give it (a mode file)

    // Material points: a parameter in [lowest, highest] (the beam: arc length from the root; a
    // mode file: the node's index) and the modes there.
    double lowest = 0.0, highest = 0.0;
    std::string parameter;  // what the parameter means, for messages
    bool whole_parameter = false;  // only whole parameters are points (a mode file's node indices)
    std::vector<double> nodes;
    std::function<ModalPoint(double)> at;

    explicit ModalModel(int m = 0);
    // Adds a mass dm at one point to the inertia integrals (a lumped mass, or a quadrature point).
    void add_mass(double dm, const ModalPoint& point);
};

}  // namespace mbd::ffrf
