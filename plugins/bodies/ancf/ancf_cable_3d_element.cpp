#include "ancf_cable_3d_element.hpp"

#include "cable_strain_energy.hpp"
#include "shared/nodal_vectors.hpp"

namespace mbd::ancf::spatial {

namespace {

using beam::Shape;
using beam::shape;

// 5-point Gauss-Legendre on [0, 1]: exact to degree 9, so the mass (degree 6), gravity and the
// axial energy (eps^2: degree 8) are integrated exactly; the curvature term is rational.
const beam::GaussRule kGauss = beam::gauss_rule(5);

Eigen::Vector3d combine(const Eigen::Vector4d& c, const Vec12& e) { return beam::combine<3>(c, e); }
Vec12 spread(const Eigen::Vector4d& c, const Eigen::Vector3d& X) { return beam::spread<3>(c, X); }
Mat12 spread2(const Eigen::Vector4d& c1, const Eigen::Vector4d& c2) { return beam::spread2<3>(c1, c2); }

// EI kappa^2 / 2 at one point, as phi(g, h, d) = EI (h / g^2 - d^2 / g^3) / 2 with g = a.a,
// h = b.b, d = a.b (a = r', b = r''), differentiated through g, h and d.
double add_bending(const Shape& f, double EI, double w, const Vec12& e, Vec12* gradient, Mat12* hessian) {
    const Eigen::Vector3d a = combine(f.ds, e), b = combine(f.dds, e);
    const double g = a.dot(a), h = b.dot(b), d = a.dot(b);
    const double g2 = g * g, g3 = g2 * g, g4 = g3 * g;
    if (gradient || hessian) {
        const Vec12 dg = spread(f.ds, 2.0 * a), dh = spread(f.dds, 2.0 * b);
        const Vec12 dd = spread(f.ds, b) + spread(f.dds, a);
        const double p_g = EI * (-h / g3 + 1.5 * d * d / g4), p_h = 0.5 * EI / g2, p_d = -EI * d / g3;
        if (gradient) *gradient += w * (p_g * dg + p_h * dh + p_d * dd);
        if (hessian) {
            const double p_gg = EI * (3.0 * h / g4 - 6.0 * d * d / (g4 * g)), p_gh = -EI / g3;
            const double p_gd = 3.0 * EI * d / g4, p_dd = -EI / g3;  // p_hh = p_hd = 0
            const Mat12 ddg = 2.0 * spread2(f.ds, f.ds), ddh = 2.0 * spread2(f.dds, f.dds);
            const Mat12 ddd = spread2(f.ds, f.dds) + spread2(f.dds, f.ds);
            *hessian += w * (p_gg * dg * dg.transpose() + p_gh * (dg * dh.transpose() + dh * dg.transpose()) +
                             p_gd * (dg * dd.transpose() + dd * dg.transpose()) + p_dd * dd * dd.transpose() +
                             p_g * ddg + p_h * ddh + p_d * ddd);
        }
    }
    return w * 0.5 * EI * (h / g2 - d * d / g3);
}

}  // namespace

Mat12 element_mass(const Section& section, double l) {
    Mat12 M = Mat12::Zero();
    for (int p = 0; p < kGauss.n; ++p) {
        const Shape f = shape(kGauss.xi[p], l);
        M += (kGauss.w[p] * l * section.rhoA) * spread2(f.s, f.s);
    }
    return M;
}

Vec12 element_gravity(const Section& section, double l, const Eigen::Vector3d& g) {
    Vec12 Q = Vec12::Zero();
    for (int p = 0; p < kGauss.n; ++p) Q += (kGauss.w[p] * l * section.rhoA) * spread(shape(kGauss.xi[p], l).s, g);
    return Q;
}

double element_strain_energy(const Section& section, double l, const Vec12& e, Vec12* gradient, Mat12* hessian) {
    return cable_strain_energy<3>(section.EA, section.EI, section.axial_points, l, e, gradient, hessian, add_bending);
}

}  // namespace mbd::ancf::spatial
