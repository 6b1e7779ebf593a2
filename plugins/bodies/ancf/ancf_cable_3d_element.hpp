// The spatial gradient-deficient ANCF cable / beam element (Gerstmayr and Shabana 2006,
// "Analysis of thin beams and cables using the absolute nodal co-ordinate formulation",
// Nonlinear Dynamics 45): two nodes, each with its position r and its slope r' = dr/dx (x the
// arc length of the straight reference configuration), so 12 coordinates
// e = [r1, r1', r2, r2'] and r(x) = S(x) e with the cubic Hermite shape functions.
//
//   mass          M_e = integral rho A S^T S dx            (constant, consistent)
//   strain energy U_e = integral (EA eps^2 + EI kappa^2) / 2 dx,
//                 eps     = (r'.r' - 1) / 2                 (Green's axial strain),
//                 kappa^2 = |r' x r''|^2 / |r'|^6
//                         = (g h - d^2) / g^3,  g = r'.r', h = r''.r'', d = r'.r''
//                 (the exact curvature of the deformed centre line, as in the planar element:
//                 it is invariant under rigid motion, independent of the axial stretch, and in a
//                 plane it is the planar element's (r' x r'')^2 / |r'|^6 by Lagrange's identity;
//                 the simpler |r''|^2 of Gerstmayr and Shabana is not zero for a stretched
//                 curved beam). The bending stiffness EI is the same about both section axes, and
//                 the element has no torsion (a cable has no twist coordinate).
// Gradient and Hessian of U_e are exact (differentiated by hand below), integrated by Gauss.
#pragma once

#include "shared/hermite.hpp"

#include <Eigen/Core>

namespace mbd::ancf::spatial {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

struct Section {
    double EA = 0.0;        // axial stiffness
    double EI = 0.0;        // bending stiffness (both section axes)
    double rhoA = 0.0;      // mass per unit length
    int axial_points = 5;   // Gauss points of the axial term (1 to 5; 5 integrates eps^2 exactly)
};

// Consistent mass matrix of an element of length l.
Mat12 element_mass(const Section& section, double l);
// Generalized force of a uniform field g on the element (constant): integral rho A S^T g dx.
Vec12 element_gravity(const Section& section, double l, const Eigen::Vector3d& g);

// Strain energy U_e and, when asked for, its gradient dU/de and Hessian d2U/de2.
double element_strain_energy(const Section& section, double l, const Vec12& e, Vec12* gradient, Mat12* hessian);

}  // namespace mbd::ancf::spatial
