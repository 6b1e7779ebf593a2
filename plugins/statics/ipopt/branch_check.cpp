// Trust region and branch check of the statics continuation (branch_check.hpp).
#include "branch_check.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace mbd::ipopt_plugin {

double IncrementGeometry::scaled_size(const Eigen::VectorXd& x) const {
    double m = 0.0;
    for (int i = 0; i < x.size(); ++i) m = std::max(m, std::abs(x[i]) / (rotation(i) ? M_PI / 2 : length));
    return m;
}

double IncrementGeometry::distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
    double d2 = 0.0;
    for (int k = 0; k < nb; ++k) {
        if (dim == Dimension::Planar) {
            d2 += (a.segment<3>(3 * k) - b.segment<3>(3 * k)).squaredNorm();  // unwrapped angles
        } else {
            d2 += (a.segment<3>(7 * k) - b.segment<3>(7 * k)).squaredNorm();
            const Eigen::Quaterniond pa(a[7 * k + 3], a[7 * k + 4], a[7 * k + 5], a[7 * k + 6]);
            const Eigen::Quaterniond pb(b[7 * k + 3], b[7 * k + 4], b[7 * k + 5], b[7 * k + 6]);
            const double angle = pa.normalized().angularDistance(pb.normalized());
            d2 += angle * angle;
        }
    }
    const int rigid = nb * coordinates_per_body(dim);  // the flexible coordinates after them
    d2 += (a.tail(a.size() - rigid) - b.tail(b.size() - rigid)).squaredNorm();
    return std::sqrt(d2);
}

IncrementGeometry increment_geometry(System& sys, const Eigen::VectorXd& q) {
    IncrementGeometry g;
    g.dim = sys.dimension();
    g.nb = sys.body_count();
    g.vpb = velocities_per_body(g.dim);
    const int cpb = coordinates_per_body(g.dim), nd = g.dim == Dimension::Planar ? 2 : 3;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
    auto extend = [&](const Eigen::Vector3d& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    };
    double reach = 0.0;
    for (int b = 0; b < g.nb; ++b) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        p.head(nd) = q.segment(cpb * b, nd);
        extend(p);
    }
    for (int j = 0; j < sys.joint_count(); ++j) {
        const JointInfo& info = sys.joint(j);
        for (size_t k = 0; k < info.bodies.size() && k < info.markers.size(); ++k) {
            if (info.bodies[k] < 0) extend(info.markers[k].u_bar);  // ground markers are world points
            else reach = std::max(reach, info.markers[k].u_bar.norm());
        }
    }
    double L = lo(0) <= hi(0) ? (hi - lo).norm() : 0.0;
    L = std::max(L, 2.0 * reach);
    g.length = L > 0.0 ? L : 1.0;
    return g;
}

bool Projector::project(double t, Eigen::VectorXd& q, double tol, int max_iterations) {
    if (mc_ == 0) return true;
    State s;
    s.t = t;
    s.v = Eigen::VectorXd::Zero(nv_);
    double first = -1.0, previous = -1.0;
    bool fresh = false;  // factorised in this call
    for (int it = 0;; ++it) {
        s.q = q;
        sys_.constraints(s, cv_, true);
        if (!cv_.C.allFinite()) return false;
        const double c = cv_.C.cwiseAbs().maxCoeff();
        if (c <= tol) return true;
        if (first < 0) first = c;
        if (it >= max_iterations || c > 1e3 * std::max(first, tol)) return false;
        if (!factored_ || (previous >= 0 && c > 0.25 * previous)) {
            if (fresh && c > 0.9 * previous) return false;  // a fresh J does not contract either
            J_ = cv_.J;
            if (!factor(J_)) return false;
            factored_ = fresh = true;
        }
        previous = c;
        const Eigen::VectorXd dx = -(J_.transpose() * ldlt_.solve(cv_.C));
        if (!dx.allFinite()) return false;
        sys_.advance_positions(q, dx);
    }
}

bool Projector::factor(const Eigen::SparseMatrix<double>& J) {
    Eigen::SparseMatrix<double> A = J * J.transpose();
    double dmax = 0.0;
    for (int i = 0; i < mc_; ++i) dmax = std::max(dmax, A.coeff(i, i));
    for (int i = 0; i < mc_; ++i) A.coeffRef(i, i) += 1e-12 * (dmax + 1e-300);  // redundant rows
    A.makeCompressed();
    if (!analysed_ || A.nonZeros() != pattern_nnz_) {
        ldlt_.analyzePattern(A);
        analysed_ = true;
        pattern_nnz_ = A.nonZeros();
    }
    ldlt_.factorize(A);
    return ldlt_.info() == Eigen::Success;
}

MarchResult march(System& sys, Projector& projector, const IncrementGeometry& geo, double t,
                  const Eigen::VectorXd& centre, const Eigen::VectorXd& x, double tol) {
    MarchResult out;
    if (sys.constraint_rows(true) == 0) return out;
    auto point = [&](double s) {
        Eigen::VectorXd p = centre;
        sys.advance_positions(p, s * x);
        return p;
    };
    const double size = geo.scaled_size(x);
    const double dt0 = 1.0 / std::max(2.0, std::ceil(size / 0.05));
    const double slack = 1e3 * tol + 1e-9 * geo.length;
    double s0 = 0.0, dt = dt0;
    Eigen::VectorXd p0 = centre, y0 = centre;
    while (s0 < 1.0) {
        const double s1 = std::min(1.0, s0 + dt);
        const Eigen::VectorXd p1 = point(s1);
        const double dp = geo.distance(p0, p1);
        Eigen::VectorXd y1 = p1;
        ++out.projections;
        bool ok = projector.project(t, y1, tol) && geo.distance(y0, y1) <= 3.0 * dp + slack;
        if (!ok && s1 < 1.0) {  // from the previous projection, advanced by the step
            y1 = y0;
            sys.advance_positions(y1, (s1 - s0) * x);
            ++out.projections;
            ok = projector.project(t, y1, tol) && geo.distance(y0, y1) <= 3.0 * dp + slack;
        }
        if (ok) {
            s0 = s1;
            p0 = p1;
            y0 = y1;
            dt = std::min(dt0, 2.0 * dt);
            continue;
        }
        dt *= 0.5;
        if (dt * std::max(size, 1e-300) < 1e-7) {
            out.connected = false;
            out.jump_at = s0;
            return out;
        }
    }
    return out;
}

}  // namespace mbd::ipopt_plugin
