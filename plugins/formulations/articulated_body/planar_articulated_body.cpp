// The recursive path's rhs in planar algebra: see planar_articulated_body.hpp.
#include "planar_articulated_body.hpp"
#include <mbd/kit/non_finite_motion.hpp>

#include <cmath>

namespace mbd::articulated {

namespace {

Vec2 perp(const Vec2& r) { return Vec2(-r.y(), r.x()); }  // k x r

Vec2 rotated(double cos_angle, double sin_angle, const Vec3& r) {
    return Vec2(cos_angle * r.x() - sin_angle * r.y(), sin_angle * r.x() + cos_angle * r.y());
}

// a freedom the planar algebra holds: a pin about +-z, a slider along an in-plane axis
bool planar_freedom(const RelativeMotion::Kind kind, const Vec3& axis) {
    constexpr double kTol = 1e-14;
    if (kind == RelativeMotion::Kind::Revolute) return std::abs(axis.x()) < kTol && std::abs(axis.y()) < kTol;
    if (kind == RelativeMotion::Kind::Prismatic) return std::abs(axis.z()) < kTol;
    return false;
}

}  // namespace

void PlanarArticulatedBody::bind(System& system, const FormulationOptions& options) {
    ArticulatedBody::bind(system, options);
    fast_ = planar_;
    for (const Edge& e : edges_)
        for (const Freedom& f : e.freedoms) fast_ = fast_ && planar_freedom(f.kind, f.axis);
    links_.assign(edges_.size(), Link{});
    link_of_body_.assign(nb_, -1);
    if (!fast_) return;
    for (size_t i = 0; i < edges_.size(); ++i) {
        const Edge& e = edges_[i];
        Link& l = links_[i];
        link_of_body_[e.body] = static_cast<int>(i);
        l.parent = e.parent >= 0 ? link_of_body_[e.parent] : -1;  // edges_ lists parents first
        l.H.setZero(3, e.nu);
        l.U.setZero(3, e.nu);
        l.Dinv.setZero(e.nu, e.nu);
        if (e.joint < 0) l.H.setIdentity();  // a free root: its own (x, y, theta)
    }
}

void PlanarArticulatedBody::planar_kinematics() {
    const Eigen::VectorXd& s = s_;
    const Eigen::VectorXd& u = u_;
    for (size_t i = 0; i < edges_.size(); ++i) {
        const Edge& e = edges_[i];
        Link& c = links_[i];
        if (e.joint < 0) {
            c.x = s[e.s0], c.y = s[e.s0 + 1], c.theta = s[e.s0 + 2];
            c.cos_theta = std::cos(c.theta), c.sin_theta = std::sin(c.theta);
            c.v = u.segment<3>(e.u0);
            c.a.setZero();
            continue;
        }
        Vec2 Rp = Vec2::Zero(), Rpdot = Vec2::Zero();
        double thp = 0.0, wp = 0.0, cos_p = 1.0, sin_p = 0.0;
        if (c.parent >= 0) {
            const Link& p = links_[c.parent];
            Rp = Vec2(p.x, p.y);
            Rpdot = p.v.head<2>();
            thp = p.theta;
            cos_p = p.cos_theta, sin_p = p.sin_theta;
            wp = p.v[2];
        }
        // the parent's joint frame, and its velocity-product acceleration at vdot_p = 0
        const Vec2 rho0 = rotated(cos_p, sin_p, e.u_p);
        Vec2 o = Rp + rho0;
        Vec2 odot = Rpdot + wp * perp(rho0);
        Vec2 oddot = -wp * wp * rho0;
        double theta = thp + e.angle_p, w = wp;
        struct Column {
            double sigma;  // pin: +-1 about z; slider: 0
            Vec2 o_or_axis;
        };
        Column cols[3];
        int ncol = 0;
        for (const Freedom& f : e.freedoms) {
            const double q = s[f.s], qd = u[f.u];
            if (f.kind == RelativeMotion::Kind::Revolute) {
                const double sigma = f.axis.z() > 0 ? 1.0 : -1.0;
                cols[ncol++] = {sigma, o};
                w += sigma * qd;
                theta += sigma * q;
            } else {  // slider along the frame's axis
                const Vec2 aw = rotated(std::cos(theta), std::sin(theta), f.axis);
                const Vec2 r = aw * q;
                cols[ncol++] = {0.0, aw};
                oddot += -w * w * r + 2.0 * w * qd * perp(aw);
                odot += w * perp(r) + aw * qd;
                o += r;
            }
        }
        c.theta = theta - e.angle_c;
        c.cos_theta = std::cos(c.theta), c.sin_theta = std::sin(c.theta);
        const Vec2 rho = -rotated(c.cos_theta, c.sin_theta, e.u_c);
        const Vec2 R = o + rho;
        c.x = R.x(), c.y = R.y();
        c.v << odot + w * perp(rho), w;
        c.a << oddot - w * w * rho, 0.0;
        c.d = perp(R - Rp);
        for (int k = 0; k < ncol; ++k) {
            if (cols[k].sigma != 0.0)
                c.H.col(k) << cols[k].sigma * perp(R - cols[k].o_or_axis), cols[k].sigma;
            else
                c.H.col(k) << cols[k].o_or_axis, 0.0;
        }
    }
}

void PlanarArticulatedBody::singular(double t, int body) const {
    throw DynamicsError(t, "embedding: the articulated inertia of body '" + system_->body(body).name +
                               "' is singular across its joint");
}

void PlanarArticulatedBody::planar_articulated(double t) {
    for (size_t i = 0; i < edges_.size(); ++i) {
        const Body& b = bodies_[edges_[i].body];
        Link& c = links_[i];
        c.P = Vec3(b.m, b.m, b.J(2, 2)).asDiagonal();
        c.z = -Q_.segment<3>(3 * edges_[i].body);
    }
    // leaves to root: articulated inertias and bias forces (articulated_body.hpp)
    for (size_t i = edges_.size(); i-- > 0;) {
        const Edge& e = edges_[i];
        Link& c = links_[i];
        Mat3 Pa;
        Vec3 za;
        if (e.prescribed >= 0) {  // known udot: the whole articulated inertia passes to the parent
            if (c.parent < 0) continue;
            Pa = c.P;
            za = c.P * (c.a + c.H.col(0) * prescribed_[e.prescribed].acceleration) + c.z;
        } else if (e.nu == 1) {  // a pin or a slider: D is a scalar (no factorization)
            const Vec3 h = c.H.col(0), U = c.P * h;
            const double D = h.dot(U);
            if (!(D > 0.0)) singular(t, e.body);
            c.U.col(0) = U;
            c.Dinv(0, 0) = 1.0 / D;
            if (c.parent < 0) continue;
            Pa = c.P - (U / D) * U.transpose();
            za = Pa * c.a + c.z - U * (h.dot(c.z) / D);
        } else {
            c.U.noalias() = c.P * c.H;
            const Mat33 D = c.H.transpose() * c.U;
            Eigen::LLT<Mat33> llt(D);
            if (llt.info() != Eigen::Success) singular(t, e.body);
            c.Dinv = llt.solve(Mat33::Identity(e.nu, e.nu));
            if (c.parent < 0) continue;
            const Mat3X UD = c.U * c.Dinv;
            Pa = c.P - UD * c.U.transpose();
            za = Pa * c.a + c.z - UD * (c.H.transpose() * c.z);
        }
        // P_p += Phi^T Pa Phi, z_p += Phi^T za with Phi = [I2 d; 0 1]
        Link& p = links_[c.parent];
        const Vec2 y12 = Pa.topLeftCorner<2, 2>() * c.d + Pa.topRightCorner<2, 1>();
        p.P.topLeftCorner<2, 2>() += Pa.topLeftCorner<2, 2>();
        p.P.topRightCorner<2, 1>() += y12;
        p.P.bottomLeftCorner<1, 2>() += y12.transpose();
        p.P(2, 2) += c.d.dot(y12) + Pa.bottomLeftCorner<1, 2>().dot(c.d) + Pa(2, 2);
        p.z.head<2>() += za.head<2>();
        p.z[2] += c.d.dot(za.head<2>()) + za[2];
    }
    // root to leaves: joint and body accelerations
    Eigen::VectorXd& udot = udot_;
    for (size_t i = 0; i < edges_.size(); ++i) {
        const Edge& e = edges_[i];
        Link& c = links_[i];
        Vec3 base = c.a;
        if (c.parent >= 0) {
            const Vec3& vp = links_[c.parent].vdot;
            base.head<2>() += vp.head<2>() + vp[2] * c.d;
            base[2] += vp[2];
        }
        if (e.prescribed >= 0) {
            const double ud = prescribed_[e.prescribed].acceleration;
            udot[e.u0] = ud;
            c.vdot = base + c.H.col(0) * ud;
        } else if (e.nu == 1) {
            const double ud = -c.Dinv(0, 0) * (c.U.col(0).dot(base) + c.H.col(0).dot(c.z));
            udot[e.u0] = ud;
            c.vdot = base + c.H.col(0) * ud;
        } else {
            const Vec3X ud = -c.Dinv * (c.U.transpose() * base + c.H.transpose() * c.z);
            udot.segment(e.u0, e.nu) = ud;
            c.vdot = base + c.H * ud;
        }
    }
    if (!udot.allFinite()) throw NonFiniteMotion(t, "non-finite accelerations: the motion diverged");
}

void PlanarArticulatedBody::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (!fast_) return ArticulatedBody::rhs(t, y, ydot);
    if (!y.allFinite()) throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
    expand(t, y);
    planar_kinematics();
    state_.t = t;
    for (size_t i = 0; i < edges_.size(); ++i) {
        const Link& c = links_[i];
        const int b = edges_[i].body;
        state_.q.segment<3>(3 * b) << c.x, c.y, c.theta;
        state_.v.segment<3>(3 * b) = c.v;
    }
    system_->generalized_forces(state_, Q_);
    if (!Q_.allFinite()) throw NonFiniteMotion(t, "non-finite generalized forces: the motion diverged");
    planar_articulated(t);
    write_ydot(y, ydot);
}

}  // namespace mbd::articulated
