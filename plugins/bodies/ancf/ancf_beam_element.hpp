// The planar shear-deformable ANCF beam element (fully parameterized: Omar and Shabana 2001,
// "A two-dimensional shear deformable beam for large rotation and deformation problems", J.
// Sound Vib. 243): two nodes, each with its position r and both gradients r_x = dr/dx and
// r_y = dr/dy (x along the reference line, y across it), so 12 coordinates
// e = [r1, r1_x, r1_y, r2, r2_x, r2_y] and, with xi = x / l,
//     r(x, y) = r_c(x) + y d(x),   r_c the cubic Hermite centre line through (r_k, r_k_x),
//                                   d = (1 - xi) r1_y + xi r2_y the cross-section's director.
//
// Locking remedy: the "structural mechanics based" elastic forces. The continuum energy of this
// element (Green-Lagrange strains over the area) locks in shear and through Poisson's coupling
// for slender beams (Gerstmayr, Matikainen and Mikkola 2008, Multibody Syst. Dyn. 20, which
// proposes measuring beam strains on the centre line instead). Here the strains are Reissner's
// (1972) geometrically exact planar beam strains read from the centre line's slope a = r_c' and
// the director d, with the section's axes e2 = d / |d| and e1 = e2 turned by -90 degrees:
//     axial     eps   = a . e1 - 1 = (a x d) / |d| - 1
//     shear     gamma = a . e2     = (a . d) / |d|
//     bending   kappa = theta'     = (d x d') / |d|^2       (theta the director's angle)
//     director  eps_d = (d . d - 1) / 2   (the section's own stretch, otherwise free)
//     U_e = integral (EA eps^2 + k G A gamma^2 + EI kappa^2 + EA eps_d^2) / 2 dx,
// by 3-point Gauss (exact for the small-deformation energy). The shear constraint gamma = 0 of a
// thin beam asks the cubic centre line's slope to follow the linear director, which it can
// everywhere, so no stiffness is spurious: a thin beam bends as Euler-Bernoulli's, the mesh's
// error being the linear director's (1 / (4 N^2) of the tip deflection under a tip load).
//
//   mass  M_e = integral (rho A S_c^T S_c + rho I S_d^T S_d) dx  (r_c's inertia and the section's
//               rotary inertia, the y-moments of the area about the centroid being 0 and I)
#pragma once

#include "shared/hermite.hpp"

#include <Eigen/Core>

namespace mbd::ancf::shear {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

struct Section {
    double EA = 0.0;     // axial stiffness (also the director's stretch)
    double kGA = 0.0;    // shear stiffness, k the shear correction factor
    double EI = 0.0;     // bending stiffness
    double rhoA = 0.0;   // mass per unit length
    double rhoI = 0.0;   // rotary inertia per unit length
};

// The element's coordinates of the centre line (Hermite order r1, r1_x, r2, r2_x) and of the
// director (r1_y, r2_y), each a 2-vector starting at these offsets.
constexpr int kCentre[4] = {0, 2, 6, 8};
constexpr int kDirector[2] = {4, 10};

Mat12 element_mass(const Section& section, double l);
// Generalized force of a uniform field g (on the centre line: the area's first moment is zero).
Vec12 element_gravity(const Section& section, double l, const Eigen::Vector2d& g);
// Strain energy U_e and, when asked for, its gradient and Hessian.
double element_strain_energy(const Section& section, double l, const Vec12& e, Vec12* gradient, Mat12* hessian);

}  // namespace mbd::ancf::shear
