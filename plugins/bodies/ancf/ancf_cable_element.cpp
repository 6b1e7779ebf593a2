#include "ancf_cable_element.hpp"

#include "cable_strain_energy.hpp"
#include "shared/nodal_vectors.hpp"

#include <cmath>

namespace mbd::ancf {

namespace {

// 5-point Gauss-Legendre on [0, 1]: exact to degree 9, so the mass (degree 6), gravity and the
// axial energy (eps^2: degree 8) are integrated exactly; the curvature term is rational.
const beam::GaussRule kGauss = beam::gauss_rule(5);

Eigen::Vector2d combine(const Eigen::Vector4d& c, const Vec8& e) { return beam::combine<2>(c, e); }
Vec8 spread(const Eigen::Vector4d& c, const Eigen::Vector2d& X) { return beam::spread<2>(c, X); }
Mat8 spread2(const Eigen::Vector4d& c1, const Eigen::Vector4d& c2, const Eigen::Matrix2d& B) {
    return beam::spread2<2>(c1, c2, B);
}

}  // namespace

Mat8 element_mass(const Section& section, double l) {
    Mat8 M = Mat8::Zero();
    for (int g = 0; g < kGauss.n; ++g) {
        const Shape f = shape(kGauss.xi[g], l);
        M += (kGauss.w[g] * l * section.rhoA) * spread2(f.s, f.s, Eigen::Matrix2d::Identity());
    }
    return M;
}

Vec8 element_gravity(const Section& section, double l, const Eigen::Vector2d& g) {
    Vec8 Q = Vec8::Zero();
    for (int p = 0; p < kGauss.n; ++p) Q += (kGauss.w[p] * l * section.rhoA) * spread(shape(kGauss.xi[p], l).s, g);
    return Q;
}

namespace {

// P with a^T P b = a x b (the planar cross product)
Eigen::Matrix2d cross_matrix() {
    Eigen::Matrix2d P;
    P << 0, 1, -1, 0;
    return P;
}

// EI kappa^2 / 2 at one point, kappa^2 = c^2 / g^3 with c = r' x r'', g = r'.r'
double add_bending(const Shape& f, double EI, double w, const Vec8& e, Vec8* gradient, Mat8* hessian) {
    const Eigen::Matrix2d P = cross_matrix();
    const Eigen::Vector2d a = combine(f.ds, e), b = combine(f.dds, e);  // r', r''
    const double g = a.dot(a), c = a.dot(P * b), g3 = g * g * g;
    if (gradient || hessian) {
        const Vec8 dg = spread(f.ds, 2.0 * a);
        const Vec8 dc = spread(f.ds, P * b) + spread(f.dds, P.transpose() * a);
        const double U_g = -1.5 * EI * c * c / (g3 * g), U_c = EI * c / g3;  // partials of the density
        if (gradient) *gradient += w * (U_g * dg + U_c * dc);
        if (hessian) {
            const double U_gg = 6.0 * EI * c * c / (g3 * g * g), U_gc = -3.0 * EI * c / (g3 * g), U_cc = EI / g3;
            const Mat8 ddg = spread2(f.ds, f.ds, 2.0 * Eigen::Matrix2d::Identity());
            const Mat8 ddc = spread2(f.ds, f.dds, P) + spread2(f.dds, f.ds, P.transpose());
            *hessian += w * (U_gg * dg * dg.transpose() + U_gc * (dg * dc.transpose() + dc * dg.transpose()) +
                             U_cc * dc * dc.transpose() + U_g * ddg + U_c * ddc);
        }
    }
    return w * 0.5 * EI * c * c / g3;
}

}  // namespace

double element_strain_energy(const Section& section, double l, const Vec8& e, Vec8* gradient, Mat8* hessian) {
    return cable_strain_energy<2>(section.EA, section.EI, section.axial_points, l, e, gradient, hessian, add_bending);
}

}  // namespace mbd::ancf
