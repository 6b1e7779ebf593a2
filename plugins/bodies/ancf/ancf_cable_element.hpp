// The planar gradient-deficient ANCF cable / Euler-Bernoulli beam element (Shabana's school:
// Berzeri and Shabana 2000; Gerstmayr and Irschik 2008): two nodes, each with its position r and
// its slope r' = dr/dx (x the arc length of the straight reference configuration), so 8
// coordinates e = [r1, r1', r2, r2'] and r(x) = S(x) e with the cubic Hermite shape functions.
//
//   mass          M_e = integral rho A S^T S dx            (constant, consistent)
//   strain energy U_e = integral (EA eps^2 + EI kappa^2) / 2 dx,
//                 eps = (r'.r' - 1) / 2 (Green's axial strain),
//                 kappa = (r' x r'') / |r'|^3 (the curvature of the deformed centre line).
// Gradient and Hessian of U_e are exact (differentiated by hand below), integrated by Gauss.
#pragma once

#include "shared/hermite.hpp"

#include <Eigen/Core>

namespace mbd::ancf {

using Vec8 = Eigen::Matrix<double, 8, 1>;
using Mat8 = Eigen::Matrix<double, 8, 8>;

// Hermite shape functions (shared/hermite.hpp): r = sum_k s[k] e_k, with e_k the k-th 2-vector
// of the element's coordinates.
using beam::Shape;
using beam::shape;

struct Section {
    double EA = 0.0;        // axial stiffness
    double EI = 0.0;        // bending stiffness
    double rhoA = 0.0;      // mass per unit length
    int axial_points = 5;   // Gauss points of the axial term (1 to 5; 5 integrates eps^2 exactly)
};

// Consistent mass matrix of an element of length l.
Mat8 element_mass(const Section& section, double l);
// Generalized force of a uniform field g on the element (constant): integral rho A S^T g dx.
Vec8 element_gravity(const Section& section, double l, const Eigen::Vector2d& g);

// Strain energy U_e and, when asked for, its gradient dU/de and Hessian d2U/de2.
double element_strain_energy(const Section& section, double l, const Vec8& e, Vec8* gradient, Mat8* hessian);

}  // namespace mbd::ancf
