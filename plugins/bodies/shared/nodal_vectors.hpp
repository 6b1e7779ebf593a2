// A cubic Hermite beam element's coordinates as four nodal D-vectors e = [e_0; e_1; e_2; e_3]
// (planar D = 2, spatial D = 3): r(x) = sum_k c_k(x) e_k for the shape functions' values or
// derivatives c (hermite.hpp). The ANCF cables build their energies and mass from these three.
#pragma once

#include <Eigen/Core>

namespace mbd::beam {

template <int D>
using NodalVector = Eigen::Matrix<double, 4 * D, 1>;
template <int D>
using NodalMatrix = Eigen::Matrix<double, 4 * D, 4 * D>;

// sum_k c[k] e_k
template <int D>
Eigen::Matrix<double, D, 1> combine(const Eigen::Vector4d& c, const NodalVector<D>& e) {
    Eigen::Matrix<double, D, 1> r = Eigen::Matrix<double, D, 1>::Zero();
    for (int k = 0; k < 4; ++k) r += c[k] * e.template segment<D>(D * k);
    return r;
}

// d/de of a^T X where a = sum_k c[k] e_k and X a fixed D-vector: blocks c[k] X
template <int D>
NodalVector<D> spread(const Eigen::Vector4d& c, const Eigen::Matrix<double, D, 1>& X) {
    NodalVector<D> out;
    for (int k = 0; k < 4; ++k) out.template segment<D>(D * k) = c[k] * X;
    return out;
}

// blocks c1[k] c2[m] B for a fixed D x D matrix B: the Hessian of a^T B b for a = sum c1[k] e_k,
// b = sum c2[m] e_m (one order)
template <int D>
NodalMatrix<D> spread2(const Eigen::Vector4d& c1, const Eigen::Vector4d& c2,
                       const Eigen::Matrix<double, D, D>& B = Eigen::Matrix<double, D, D>::Identity()) {
    NodalMatrix<D> out;
    for (int k = 0; k < 4; ++k)
        for (int m = 0; m < 4; ++m) out.template block<D, D>(D * k, D * m) = c1[k] * c2[m] * B;
    return out;
}

}  // namespace mbd::beam
