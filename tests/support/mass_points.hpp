// The mass points of a uniform flexible body for integrals over its mass (momenta, angular
// momentum, gravity's moment) in tests: 4-point Gauss-Legendre on each element of the arc length,
// exact for the cubic centre lines of the ANCF cable and the ffrf beam times their rates.
#pragma once

#include <mbd/model.hpp>
#include <mbd/sdk/body.hpp>

#include <Eigen/Core>

namespace mbd::test {

// visit(dm, point) for each Gauss point of each of `elements` equal elements of `length`, with the
// point's position and velocity at state s; mass per length rho_a
template <class Visit>
void for_each_mass_point(const FlexibleBodyInstance& f, const State& s, int elements, double length, double rho_a,
                         Visit&& visit) {
    static const double xi[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    static const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    const Eigen::VectorXd q = s.q.segment(f.offset, f.size), v = s.v.segment(f.v_offset, f.size);
    const double l = length / elements;
    MaterialPoint p;
    for (int j = 0; j < elements; ++j)
        for (int g = 0; g < 4; ++g) {
            const double x = (j + 0.5 + 0.5 * xi[g]) * l;
            f.body->point(q, v, &x, p);
            visit(rho_a * 0.5 * w[g] * l, p);
        }
}

}  // namespace mbd::test
