// Cubic Hermite interpolation on a beam element and Gauss-Legendre rules on [0, 1]: shared by the
// ANCF elements (plugins/bodies/ancf) and the Euler-Bernoulli mesh whose modes the FFRF body uses
// (plugins/bodies/ffrf). Header-only: each body plugin is its own shared library.
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace mbd::beam {

// Hermite shape functions at xi = x / l in [0, 1] and their first and second x-derivatives, for
// nodal values [f(0), f'(0), f(l), f'(l)]: f(x) = s . [f(0), f'(0), f(l), f'(l)].
struct Shape {
    Eigen::Vector4d s, ds, dds;
};
inline Shape shape(double xi, double l) {
    const double x2 = xi * xi, x3 = x2 * xi;
    Shape f;
    f.s << 1 - 3 * x2 + 2 * x3, l * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3, l * (x3 - x2);
    f.ds << (-6 * xi + 6 * x2) / l, 1 - 4 * xi + 3 * x2, (6 * xi - 6 * x2) / l, 3 * x2 - 2 * xi;
    f.dds << (-6 + 12 * xi) / (l * l), (-4 + 6 * xi) / l, (6 - 12 * xi) / (l * l), (6 * xi - 2) / l;
    return f;
}

// An n-point Gauss-Legendre rule on [0, 1] (n from 1 to 5; exact to degree 2n - 1).
struct GaussRule {
    int n;
    double xi[5], w[5];
};
inline GaussRule gauss_rule(int n) {
    const double a2 = 1.0 / std::sqrt(3.0), a3 = std::sqrt(0.6);
    const double a4[2] = {0.3399810435848563, 0.8611363115940526}, w4[2] = {0.6521451548625461, 0.3478548451374538};
    const double a5[2] = {0.5384693101056831, 0.9061798459386640}, w5[3] = {0.5688888888888889, 0.4786286704993665,
                                                                            0.2369268850561891};
    switch (n) {
        case 1: return {1, {0.5}, {1.0}};
        case 2: return {2, {0.5 * (1 - a2), 0.5 * (1 + a2)}, {0.5, 0.5}};
        case 3: return {3, {0.5 * (1 - a3), 0.5, 0.5 * (1 + a3)}, {5.0 / 18, 8.0 / 18, 5.0 / 18}};
        case 4:
            return {4,
                    {0.5 * (1 - a4[1]), 0.5 * (1 - a4[0]), 0.5 * (1 + a4[0]), 0.5 * (1 + a4[1])},
                    {0.5 * w4[1], 0.5 * w4[0], 0.5 * w4[0], 0.5 * w4[1]}};
        default:
            return {5,
                    {0.5 * (1 - a5[1]), 0.5 * (1 - a5[0]), 0.5, 0.5 * (1 + a5[0]), 0.5 * (1 + a5[1])},
                    {0.5 * w5[2], 0.5 * w5[1], 0.5 * w5[0], 0.5 * w5[1], 0.5 * w5[2]}};
    }
}

}  // namespace mbd::beam
