// Flexible body plugins (sdk body.hpp) driven directly by tests: a body made from its keys as a
// scene would give them, the coordinates left free when some are held, and the finite-difference
// check of a material frame's Jacobian and bias. Shared by test_ancf_cable and test_ffrf_body.
#pragma once

#include "support/test_support.hpp"

#include <mbd/sdk/body.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace mbd::test {

// Scene parameters at "beam.yaml:3", as the scene loader would hand them to a plugin.
inline Param scalar_param(const std::string& text) {
    Param p;
    p.text = text;
    p.file = "beam.yaml";
    p.line = 3;
    return p;
}
inline Param number_param(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return scalar_param(buf);
}
inline Param list_param(const std::vector<double>& values) {
    Param p = scalar_param("");
    p.kind = Param::Kind::List;
    for (double v : values) p.items.push_back(number_param(v));
    return p;
}

// A body named 'beam' of `type` made from `fields` (the node outlives the body: both are held here).
struct BodyFromKeys {
    Param node;
    BodySpec spec;
    std::shared_ptr<const FlexibleBody> body;
};
inline std::unique_ptr<BodyFromKeys> make_body(const std::string& type, const std::map<std::string, Param>& fields) {
    auto b = std::make_unique<BodyFromKeys>();
    b->node = scalar_param("");
    b->node.kind = Param::Kind::Map;
    b->node.fields = fields;
    b->spec = {"beam", type, Dimension::Planar, Params("body 'beam'", &b->node)};
    b->body = shared_registry().create_body(b->spec, "beam.yaml:2");
    return b;
}

// The coordinates left free when the first `held` are held (a clamp or pin that is linear in
// the coordinates is held by leaving them out).
struct Reduced {
    std::vector<int> free;
    Reduced(int n, int held) {
        for (int k = held; k < n; ++k) free.push_back(k);
    }
    int size() const { return static_cast<int>(free.size()); }
    Eigen::VectorXd take(const Eigen::VectorXd& full) const { return full(free); }
    Eigen::MatrixXd take(const Eigen::MatrixXd& full) const { return full(free, free); }
    void put(const Eigen::VectorXd& part, Eigen::VectorXd& full) const { full(free) = part; }
};

// A planar material frame's velocity is G v and its acceleration G vdot + a: along q + t v with
// v fixed (vdot = 0) the central differences of its pose are G v and those of its velocity a.
// Also: the material point at xi moves with the frame's origin, and its Jacobian maps v to rdot.
inline void expect_frame_derivatives(const FlexibleBody& body, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                     double xi, double tolerance) {
    const double h = 1e-6;
    MaterialFrame f, fp, fm;
    body.frame(q, v, &xi, f);
    body.frame(q + h * v, v, &xi, fp);
    body.frame(q - h * v, v, &xi, fm);
    const Eigen::Vector3d rate((fp.planar.R.x() - fm.planar.R.x()) / (2 * h), (fp.planar.R.y() - fm.planar.R.y()) / (2 * h),
                               (fp.planar.theta - fm.planar.theta) / (2 * h));
    const Eigen::Vector3d velocity(f.planar.Rdot.x(), f.planar.Rdot.y(), f.planar.omega);
    const Eigen::Vector3d acceleration((fp.planar.Rdot.x() - fm.planar.Rdot.x()) / (2 * h),
                                       (fp.planar.Rdot.y() - fm.planar.Rdot.y()) / (2 * h),
                                       (fp.planar.omega - fm.planar.omega) / (2 * h));
    EXPECT_LT((rate - f.jacobian * v).norm(), tolerance * (1 + rate.norm())) << "G v at " << xi;
    EXPECT_LT((velocity - f.jacobian * v).norm(), 1e-12 * (1 + velocity.norm())) << "the frame's velocity at " << xi;
    EXPECT_LT((acceleration - f.bias).norm(), tolerance * (1 + acceleration.norm())) << "bias at " << xi;
    MaterialPoint pt;
    body.point(q, v, &xi, pt);
    EXPECT_LT((pt.rdot - pt.jacobian * v).norm(), 1e-12 * (1 + pt.rdot.norm()));
    EXPECT_LT((pt.r.head<2>() - f.planar.R).norm(), 1e-14 * (1 + pt.r.norm()));
    EXPECT_LT((pt.rdot.head<2>() - f.planar.Rdot).norm(), 1e-12 * (1 + pt.rdot.norm()));
}

// A body's elastic forces are -dU/dq and its stiffness their Jacobian (symmetric, a Hessian),
// checked at q by central differences: error h^2 times the third derivative (about 1e-12
// relative here) plus round-off U eps / h (about 1e-10 relative), so 1e-7 of each norm.
inline void expect_elastic_derivatives(const FlexibleBody& body, const Eigen::VectorXd& q) {
    const int n = body.coordinates();
    Eigen::VectorXd Q(n), Qp(n), Qm(n);
    Eigen::MatrixXd dQ(n, n);
    body.elastic_forces(q, Q);
    body.elastic_jacobian(q, dQ);
    EXPECT_LT((dQ - dQ.transpose()).norm(), 1e-12 * dQ.norm()) << "a Hessian is symmetric";
    const double h = 1e-6;
    double force_error = 0.0, stiffness_error = 0.0;
    for (int k = 0; k < n; ++k) {
        Eigen::VectorXd qp = q, qm = q;
        qp[k] += h, qm[k] -= h;
        force_error = std::max(force_error, std::abs(-(body.strain_energy(qp) - body.strain_energy(qm)) / (2 * h) - Q[k]));
        body.elastic_forces(qp, Qp);
        body.elastic_forces(qm, Qm);
        stiffness_error = std::max(stiffness_error, ((Qp - Qm) / (2 * h) - dQ.col(k)).norm());
    }
    std::printf("finite differences: force %.2e of %.2e, stiffness %.2e of %.2e\n", force_error, Q.norm(),
                stiffness_error, dQ.norm());
    EXPECT_LT(force_error, 1e-7 * Q.norm());
    EXPECT_LT(stiffness_error, 1e-7 * dQ.norm());
}

}  // namespace mbd::test
