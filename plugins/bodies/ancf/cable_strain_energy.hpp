// The strain energy of a gradient-deficient ANCF cable element (planar D = 2, spatial D = 3),
// with its gradient and Hessian when asked: the axial term EA eps^2 / 2, eps = (r'.r' - 1) / 2
// (Green's strain, the same in both), integrated by `axial_points` Gauss points (fewer relieve
// membrane locking), plus the bending term each element gives (its curvature differs with D),
// integrated by 5 points. Shared by ancf_cable_element.cpp and ancf_cable_3d_element.cpp.
#pragma once

#include "shared/hermite.hpp"
#include "shared/nodal_vectors.hpp"

namespace mbd::ancf {

// EA eps^2 / 2 at one point, with its gradient and Hessian added (weight w)
template <int D>
double add_axial_strain(const beam::Shape& f, double EA, double w, const beam::NodalVector<D>& e,
                        beam::NodalVector<D>* gradient, beam::NodalMatrix<D>* hessian) {
    const Eigen::Matrix<double, D, 1> a = beam::combine<D>(f.ds, e);  // r'
    const double eps = 0.5 * (a.dot(a) - 1.0);
    const beam::NodalVector<D> d_eps = beam::spread<D>(f.ds, a);
    if (gradient) *gradient += (w * EA * eps) * d_eps;
    if (hessian) *hessian += (w * EA) * (d_eps * d_eps.transpose() + eps * beam::spread2<D>(f.ds, f.ds));
    return w * 0.5 * EA * eps * eps;
}

// add_bending(shape, EI, weight, e, gradient, hessian): the element's bending term at one point
template <int D, class Bending>
double cable_strain_energy(double EA, double EI, int axial_points, double l, const beam::NodalVector<D>& e,
                           beam::NodalVector<D>* gradient, beam::NodalMatrix<D>* hessian, const Bending& add_bending) {
    if (gradient) gradient->setZero();
    if (hessian) hessian->setZero();
    double U = 0.0;
    const beam::GaussRule axial = beam::gauss_rule(axial_points), bending = beam::gauss_rule(5);
    for (int p = 0; p < axial.n; ++p)
        U += add_axial_strain<D>(beam::shape(axial.xi[p], l), EA, axial.w[p] * l, e, gradient, hessian);
    for (int p = 0; p < bending.n; ++p)
        U += add_bending(beam::shape(bending.xi[p], l), EI, bending.w[p] * l, e, gradient, hessian);
    return U;
}

}  // namespace mbd::ancf
