#include "ancf_beam_element.hpp"

#include <cmath>

namespace mbd::ancf::shear {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat6x12 = Eigen::Matrix<double, 6, 12>;

// The strains are functions of z = [a, d, b] at a point (a = r_c', d the director, b = d'), each
// a 2-vector; z = L e is linear in the element's coordinates.
struct Local {
    Vec6 z;
    Mat6x12 L = Mat6x12::Zero();
};
Local local(double xi, double l, const Vec12& e) {
    const beam::Shape f = beam::shape(xi, l);
    Local at;
    for (int k = 0; k < 4; ++k) at.L.block<2, 2>(0, kCentre[k]).diagonal().setConstant(f.ds[k]);
    at.L.block<2, 2>(2, kDirector[0]).diagonal().setConstant(1.0 - xi);
    at.L.block<2, 2>(2, kDirector[1]).diagonal().setConstant(xi);
    at.L.block<2, 2>(4, kDirector[0]).diagonal().setConstant(-1.0 / l);
    at.L.block<2, 2>(4, kDirector[1]).diagonal().setConstant(1.0 / l);
    at.z = at.L * e;
    return at;
}

// A scalar function of z with its gradient and Hessian.
struct Field {
    double v = 0.0;
    Vec6 g = Vec6::Zero();
    Mat6 H = Mat6::Zero();
};

// z_i^T M z_j for the 2-vectors i, j of z (0: a, 1: d, 2: b).
Field bilinear(const Vec6& z, int i, int j, const Eigen::Matrix2d& M) {
    Field f;
    f.v = z.segment<2>(2 * i).dot(M * z.segment<2>(2 * j));
    f.g.segment<2>(2 * i) += M * z.segment<2>(2 * j);
    f.g.segment<2>(2 * j) += M.transpose() * z.segment<2>(2 * i);
    f.H.block<2, 2>(2 * i, 2 * j) += M;
    f.H.block<2, 2>(2 * j, 2 * i) += M.transpose();
    return f;
}

// (d . d)^alpha
Field director_power(const Vec6& z, double alpha) {
    const Eigen::Vector2d d = z.segment<2>(2);
    const double s = d.dot(d);
    Field f;
    f.v = std::pow(s, alpha);
    f.g.segment<2>(2) = 2.0 * alpha * std::pow(s, alpha - 1.0) * d;
    f.H.block<2, 2>(2, 2) = 2.0 * alpha * std::pow(s, alpha - 1.0) * Eigen::Matrix2d::Identity() +
                            4.0 * alpha * (alpha - 1.0) * std::pow(s, alpha - 2.0) * d * d.transpose();
    return f;
}

Field product(const Field& x, const Field& y) {
    Field f;
    f.v = x.v * y.v;
    f.g = x.v * y.g + y.v * x.g;
    f.H = x.v * y.H + y.v * x.H + x.g * y.g.transpose() + y.g * x.g.transpose();
    return f;
}

// C sigma^2 / 2 into the energy density (value, gradient, Hessian in z)
void add_term(double C, const Field& sigma, Field& density) {
    density.v += 0.5 * C * sigma.v * sigma.v;
    density.g += C * sigma.v * sigma.g;
    density.H += C * (sigma.g * sigma.g.transpose() + sigma.v * sigma.H);
}

// The energy density of Reissner's strains at a point (ancf_beam_element.hpp).
Field energy_density(const Section& section, const Vec6& z) {
    Eigen::Matrix2d P;  // x^T P y = x cross y
    P << 0, 1, -1, 0;
    const Field inverse_length = director_power(z, -0.5), inverse_square = director_power(z, -1.0);
    Field eps = product(bilinear(z, 0, 1, P), inverse_length);
    eps.v -= 1.0;
    const Field gamma = product(bilinear(z, 0, 1, Eigen::Matrix2d::Identity()), inverse_length);
    const Field kappa = product(bilinear(z, 1, 2, P), inverse_square);
    Field eps_d = bilinear(z, 1, 1, 0.5 * Eigen::Matrix2d::Identity());
    eps_d.v -= 0.5;
    Field density;
    add_term(section.EA, eps, density);
    add_term(section.kGA, gamma, density);
    add_term(section.EI, kappa, density);
    add_term(section.EA, eps_d, density);
    return density;
}

}  // namespace

Mat12 element_mass(const Section& section, double l) {
    const beam::GaussRule rule = beam::gauss_rule(5);  // exact: the integrands are of degree 6 at most
    Mat12 M = Mat12::Zero();
    for (int p = 0; p < rule.n; ++p) {
        const double xi = rule.xi[p];
        const beam::Shape f = beam::shape(xi, l);
        Eigen::Matrix<double, 2, 12> Sc = Eigen::Matrix<double, 2, 12>::Zero(), Sd = Sc;
        for (int k = 0; k < 4; ++k) Sc.block<2, 2>(0, kCentre[k]).diagonal().setConstant(f.s[k]);
        Sd.block<2, 2>(0, kDirector[0]).diagonal().setConstant(1.0 - xi);
        Sd.block<2, 2>(0, kDirector[1]).diagonal().setConstant(xi);
        M += rule.w[p] * l * (section.rhoA * Sc.transpose() * Sc + section.rhoI * Sd.transpose() * Sd);
    }
    return M;
}

Vec12 element_gravity(const Section& section, double l, const Eigen::Vector2d& g) {
    const beam::GaussRule rule = beam::gauss_rule(5);
    Vec12 Q = Vec12::Zero();
    for (int p = 0; p < rule.n; ++p) {
        const beam::Shape f = beam::shape(rule.xi[p], l);
        for (int k = 0; k < 4; ++k) Q.segment<2>(kCentre[k]) += rule.w[p] * l * section.rhoA * f.s[k] * g;
    }
    return Q;
}

double element_strain_energy(const Section& section, double l, const Vec12& e, Vec12* gradient, Mat12* hessian) {
    if (gradient) gradient->setZero();
    if (hessian) hessian->setZero();
    const beam::GaussRule rule = beam::gauss_rule(3);
    double U = 0.0;
    for (int p = 0; p < rule.n; ++p) {
        const Local at = local(rule.xi[p], l, e);
        const Field density = energy_density(section, at.z);
        const double w = rule.w[p] * l;
        U += w * density.v;
        if (gradient) *gradient += w * at.L.transpose() * density.g;
        if (hessian) *hessian += w * at.L.transpose() * density.H * at.L;
    }
    return U;
}

}  // namespace mbd::ancf::shear
