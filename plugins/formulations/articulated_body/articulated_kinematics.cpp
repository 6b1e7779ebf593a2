// The articulated body's kinematics (articulated_body.hpp): forward, from the joint
// coordinates and speeds to the bodies' poses, velocities, Phi, H and velocity-product
// accelerations; and back, from a state's poses and velocities to the joint coordinates.
#include "articulated_body.hpp"

#include <cmath>

namespace mbd::articulated {

namespace {

// angle of the rotation R about the unit axis a (R assumed to be such a rotation)
double angle_about(const Vec3& a, const Mat3& R) {
    const Vec3 e = any_perpendicular(a);
    const Vec3 re = R * e;
    return std::atan2(a.dot(e.cross(re)), e.dot(re));
}

// angle about the unit axis a that takes the direction x to the direction y (projected on the plane normal to a)
double angle_taking(const Vec3& a, const Vec3& x, const Vec3& y) {
    const Vec3 xp = x - a.dot(x) * a, yp = y - a.dot(y) * a;
    return std::atan2(a.dot(xp.cross(yp)), xp.dot(yp));
}

bool rotational(RelativeMotion::Kind k) { return k == RelativeMotion::Kind::Revolute || k == RelativeMotion::Kind::Helical; }

Vec4 conjugate(const Vec4& p) { return Vec4(p[0], -p[1], -p[2], -p[3]); }

}  // namespace

void ArticulatedBody::kinematics(const Eigen::VectorXd& s, const Eigen::VectorXd& u) {
    HColumn cols[6];
    for (const Edge& e : edges_) {
        if (e.joint < 0) {
            root_kinematics(e, s, u);
            continue;
        }
        JointFrame frame = parent_marker_frame(e);
        const int ncol = walk_freedoms(e, s, u, frame, cols);
        place_child(e, frame, cols, ncol);
    }
}

void ArticulatedBody::root_kinematics(const Edge& e, const Eigen::VectorXd& s, const Eigen::VectorXd& u) {
    Body& c = bodies_[e.body];
    c.S.setZero();
    c.E.setZero();
    c.a.setZero();
    auto Hc = H(e);
    Hc.setZero();
    if (planar_) {
        c.R = Vec3(s[e.s0], s[e.s0 + 1], 0.0);
        c.theta = s[e.s0 + 2];
        c.A = rotation_z(c.theta);
        c.v << u[e.u0], u[e.u0 + 1], 0, 0, 0, u[e.u0 + 2];
        Hc(0, 0) = Hc(1, 1) = Hc(5, 2) = 1.0;
    } else {
        c.R = s.segment<3>(e.s0);
        const Vec4 p = s.segment<4>(e.s0 + 3);
        c.p = p / p.norm();
        c.A = rotation_from_euler_parameters(c.p);
        c.v = u.segment<6>(e.u0);
        Hc.setIdentity();
    }
    c.w = c.A * c.v.tail<3>();
}

ArticulatedBody::JointFrame ArticulatedBody::parent_marker_frame(const Edge& e) const {
    JointFrame f;
    Vec3 Rpdot = Vec3::Zero(), wp = Vec3::Zero();
    Vec4 pp(1, 0, 0, 0);
    double thp = 0.0;
    if (e.parent >= 0) {
        const Body& p = bodies_[e.parent];
        f.Rp = p.R;
        f.Ap = p.A;
        pp = p.p;
        thp = p.theta;
        Rpdot = p.v.head<3>();
        wp = p.w;
    }
    // the parent's joint frame; velocity-product terms with vdot_p = 0 (alpha_p = 0)
    const Vec3 rho0 = f.Ap * e.u_p;
    f.o = f.Rp + rho0;
    f.A = f.Ap * e.A_p;
    f.p = planar_ ? pp : quaternion_product(pp, e.p_p);
    f.theta = thp + e.angle_p;
    f.w = wp;
    f.alpha = Vec3::Zero();
    f.odot = Rpdot + wp.cross(rho0);
    f.oddot = wp.cross(wp.cross(rho0));
    return f;
}

int ArticulatedBody::walk_freedoms(const Edge& e, const Eigen::VectorXd& s, const Eigen::VectorXd& u, JointFrame& f,
                                   HColumn* cols) const {
    int ncol = 0;
    for (const Freedom& g : e.freedoms) {
        if (g.kind == RelativeMotion::Kind::Ball) {
            const Vec4 p = s.segment<4>(g.s) / s.segment<4>(g.s).norm();
            f.A = f.A * rotation_from_euler_parameters(p);
            if (!planar_) f.p = quaternion_product(f.p, p);
            const Vec3 ww = f.A * u.segment<3>(g.u);
            for (int m = 0; m < 3; ++m) cols[ncol++] = {f.A.col(m), f.o, Vec3::Zero()};
            f.alpha += f.w.cross(ww);
            f.w += ww;
            continue;
        }
        const double q = s[g.s], qd = u[g.u];
        const Vec3 aw = f.A * g.axis;
        if (rotational(g.kind)) {
            const Vec3 r = aw * (g.pitch * q);
            const Vec3 lin = aw * g.pitch;
            cols[ncol++] = {aw, f.o, lin};
            f.oddot += f.alpha.cross(r) + f.w.cross(f.w.cross(r)) + 2.0 * f.w.cross(lin * qd);
            f.odot += f.w.cross(r) + lin * qd;
            f.o += r;
            f.alpha += f.w.cross(aw * qd);
            f.w += aw * qd;
            f.A = f.A * Eigen::AngleAxisd(q, g.axis).toRotationMatrix();
            if (planar_)
                f.theta += g.axis.z() > 0 ? q : -q;
            else
                f.p = quaternion_product(f.p, euler_parameters_from_axis_angle(g.axis, q));
        } else {  // prismatic
            const Vec3 r = aw * q;
            cols[ncol++] = {Vec3::Zero(), f.o, aw};
            f.oddot += f.alpha.cross(r) + f.w.cross(f.w.cross(r)) + 2.0 * f.w.cross(aw * qd);
            f.odot += f.w.cross(r) + aw * qd;
            f.o += r;
        }
    }
    return ncol;
}

void ArticulatedBody::place_child(const Edge& e, const JointFrame& f, const HColumn* cols, int ncol) {
    Body& c = bodies_[e.body];
    if (planar_) {
        c.theta = f.theta - e.angle_c;
        c.A = rotation_z(c.theta);
    } else {
        c.A = f.A * e.A_c.transpose();
        c.p = quaternion_product(f.p, conjugate(e.p_c));
    }
    const Vec3 rho = -(c.A * e.u_c);
    c.R = f.o + rho;
    c.w = f.w;
    c.v.head<3>() = f.odot + f.w.cross(rho);
    c.v.tail<3>() = c.A.transpose() * f.w;
    c.a.head<3>() = f.oddot + f.alpha.cross(rho) + f.w.cross(f.w.cross(rho));
    c.a.tail<3>() = c.A.transpose() * f.alpha;
    auto Hc = H(e);
    for (int k = 0; k < ncol; ++k) {
        Hc.col(k).head<3>() = cols[k].g.cross(c.R - cols[k].o) + cols[k].t;
        Hc.col(k).tail<3>() = c.A.transpose() * cols[k].g;
    }
    c.S = -skew(c.R - f.Rp) * f.Ap;
    c.E = c.A.transpose() * f.Ap;
}

void ArticulatedBody::write_state(double t, State& state) {
    state.t = t;
    state.q.resize(nq_);
    state.v.resize(nv_);
    for (int b = 0; b < nb_; ++b) {
        const Body& body = bodies_[b];
        if (planar_) {
            state.q.segment<3>(3 * b) << body.R.x(), body.R.y(), body.theta;
            state.v.segment<3>(3 * b) << body.v[0], body.v[1], body.v[5];
        } else {
            state.q.segment<3>(7 * b) = body.R;
            state.q.segment<4>(7 * b + 3) = sign_[b] * body.p;
            state.v.segment<6>(6 * b) = body.v;
        }
    }
}

void ArticulatedBody::joint_coordinates(const State& state) {
    s_.setZero(ns_);
    for (const Edge& e : edges_) edge_coordinates(state, e);
    joint_speeds(state);
}

void ArticulatedBody::body_pose(const State& state, int b, Vec3& R, Mat3& A, double& theta) const {
    if (b < 0) {
        R.setZero();
        A.setIdentity();
        theta = 0.0;
    } else if (planar_) {
        R = Vec3(state.q[3 * b], state.q[3 * b + 1], 0.0);
        theta = state.q[3 * b + 2];
        A = rotation_z(theta);
    } else {
        R = state.q.segment<3>(7 * b);
        const Vec4 p = state.q.segment<4>(7 * b + 3);
        A = rotation_from_euler_parameters(p / p.norm());
        theta = 0.0;
    }
}

// joint coordinates: decompose the joint's relative pose into its freedoms
void ArticulatedBody::edge_coordinates(const State& state, const Edge& e) {
    Eigen::VectorXd& s = s_;
    if (e.joint < 0) {
        if (planar_)
            s.segment<3>(e.s0) = state.q.segment<3>(3 * e.body);
        else
            s.segment<7>(e.s0) = state.q.segment<7>(7 * e.body);
        return;
    }
    Vec3 Rc, Rp;
    Mat3 Ac, Ap;
    double thc, thp;
    body_pose(state, e.body, Rc, Ac, thc);
    body_pose(state, e.parent, Rp, Ap, thp);
    const Mat3 F0 = Ap * e.A_p, Fn = Ac * e.A_c;
    const Mat3 Rrel = F0.transpose() * Fn;
    std::vector<const Freedom*> rots;
    for (const Freedom& f : e.freedoms)
        if (f.kind != RelativeMotion::Kind::Prismatic) rots.push_back(&f);
    if (rots.size() == 1 && rots[0]->kind == RelativeMotion::Kind::Ball) {
        s.segment<4>(rots[0]->s) = euler_parameters_from_rotation(Rrel);
    } else if (rots.size() == 1) {
        if (planar_) {  // unwrapped: the difference of the frames' absolute angles
            const double rel = (thc + e.angle_c) - (thp + e.angle_p);
            s[rots[0]->s] = rots[0]->axis.z() > 0 ? rel : -rel;
        } else {
            s[rots[0]->s] = angle_about(rots[0]->axis, Rrel);
        }
    } else if (rots.size() == 2) {
        const Vec3 &a1 = rots[0]->axis, &a2 = rots[1]->axis;
        const double s1 = angle_taking(a1, a2, Rrel * a2);
        s[rots[0]->s] = s1;
        s[rots[1]->s] = angle_about(a2, Eigen::AngleAxisd(s1, a1).toRotationMatrix().transpose() * Rrel);
    }
    prismatic_coordinates(e, F0.transpose() * (Rc + Ac * e.u_c - Rp - Ap * e.u_p));
}

// the prismatic coordinates of an edge whose rotations are in s_, from the relative
// displacement drel (joint-frame axes): drel = sum_k R_{<k} t_k, linear in them
void ArticulatedBody::prismatic_coordinates(const Edge& e, const Vec3& drel) {
    Eigen::VectorXd& s = s_;
    Mat3 Rk = Mat3::Identity();
    Vec3 known = Vec3::Zero();
    Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 6> C(3, 0);
    std::vector<int> prismatic;
    for (const Freedom& f : e.freedoms) {
        if (f.kind == RelativeMotion::Kind::Prismatic) {
            C.conservativeResize(3, C.cols() + 1);
            C.col(C.cols() - 1) = Rk * f.axis;
            prismatic.push_back(f.s);
        } else if (f.kind == RelativeMotion::Kind::Ball) {
            const Vec4 p = s.segment<4>(f.s);
            Rk = Rk * rotation_from_euler_parameters(p);
        } else {
            known += Rk * f.axis * (f.pitch * s[f.s]);
            Rk = Rk * Eigen::AngleAxisd(s[f.s], f.axis).toRotationMatrix();
        }
    }
    if (!prismatic.empty()) {
        const Eigen::VectorXd x = (C.transpose() * C).ldlt().solve(C.transpose() * (drel - known));
        for (size_t k = 0; k < prismatic.size(); ++k) s[prismatic[k]] = x[k];
    }
}

// speeds: kinematics at s (u = 0) gives Phi and H; u = H^+ (v_c - Phi v_p) per edge
void ArticulatedBody::joint_speeds(const State& state) {
    Eigen::VectorXd& u = u_;
    u.setZero(nu_);
    kinematics(s_, u);
    for (int b = 0; b < nb_ && !planar_; ++b)
        sign_[b] = bodies_[b].p.dot(state.q.segment<4>(7 * b + 3)) < 0 ? -1.0 : 1.0;
    for (const Edge& e : edges_) {
        const Body& c = bodies_[e.body];
        Vec6 rel = to6(state.v, e.body);
        if (e.parent >= 0) rel -= phi_mul(c, to6(state.v, e.parent));
        const auto Hc = H(e);
        const MatXX6 HtH = Hc.transpose() * Hc;
        u.segment(e.u0, e.nu) = HtH.ldlt().solve(Hc.transpose() * rel);
    }
}

}  // namespace mbd::articulated
