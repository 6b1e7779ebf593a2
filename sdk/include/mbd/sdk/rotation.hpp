// Rotation helpers shared by the core and plugins.
//
// Spatial bodies carry Euler parameters p = [e0, e1, e2, e3] (book Sec. 8.3) as
// coordinates and the body-frame angular velocity w_bar as velocities. The
// kinematic relation is pdot = 1/2 Gbar^T w_bar with w_bar = 2 Gbar pdot
// (book Eqs. 8.45-8.48 in Euler-parameter form), Gbar the 3x4 matrix below.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace mbd {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;

inline Mat3 skew(const Vec3& a) {
    Mat3 s;
    s << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return s;
}

// Planar rotation matrix A(theta) (book Eq. 3.22) and its derivative A_theta (Eq. 3.28).
inline Mat2 planar_rotation(double theta) {
    const double c = std::cos(theta), s = std::sin(theta);
    Mat2 a;
    a << c, -s, s, c;
    return a;
}
inline Mat2 planar_rotation_derivative(double theta) {
    const double c = std::cos(theta), s = std::sin(theta);
    Mat2 a;
    a << -s, -c, c, -s;
    return a;
}
// Planar cross product of a 2-vector rotated by +90 degrees: perp(u) = A_theta A^T u.
inline Vec2 perp(const Vec2& u) { return Vec2(-u.y(), u.x()); }

// Rotation matrix of Euler parameters (book Eq. 8.19); p need not be exactly unit.
inline Mat3 rotation_from_euler_parameters(const Vec4& p) {
    const double e0 = p[0], e1 = p[1], e2 = p[2], e3 = p[3];
    Mat3 a;
    a << 2 * (e0 * e0 + e1 * e1) - 1, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2),
        2 * (e1 * e2 + e0 * e3), 2 * (e0 * e0 + e2 * e2) - 1, 2 * (e2 * e3 - e0 * e1),
        2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 2 * (e0 * e0 + e3 * e3) - 1;
    return a;
}

// G (global) and Gbar (body) 3x4 matrices of Euler parameters (book Eqs. 8.40-8.44):
// w = 2 G pdot, w_bar = 2 Gbar pdot.
inline Eigen::Matrix<double, 3, 4> euler_G(const Vec4& p) {
    Eigen::Matrix<double, 3, 4> g;
    g << -p[1], p[0], -p[3], p[2], -p[2], p[3], p[0], -p[1], -p[3], -p[2], p[1], p[0];
    return g;
}
inline Eigen::Matrix<double, 3, 4> euler_Gbar(const Vec4& p) {
    Eigen::Matrix<double, 3, 4> g;
    g << -p[1], p[0], p[3], -p[2], -p[2], -p[3], p[0], p[1], -p[3], p[2], -p[1], p[0];
    return g;
}

// Euler parameters of a rotation matrix (Shepperd's method, robust at every attitude).
inline Vec4 euler_parameters_from_rotation(const Mat3& a) {
    Eigen::Quaterniond q(a);
    q.normalize();
    Vec4 p(q.w(), q.x(), q.y(), q.z());
    if (p[0] < 0) p = -p;
    return p;
}

inline Vec4 euler_parameters_from_axis_angle(const Vec3& axis, double angle) {
    const Vec3 n = axis.normalized();
    return Vec4(std::cos(angle / 2), n.x() * std::sin(angle / 2), n.y() * std::sin(angle / 2),
                n.z() * std::sin(angle / 2));
}

// Quaternion product a (x) b with the scalar first.
inline Vec4 quaternion_product(const Vec4& a, const Vec4& b) {
    Vec4 r;
    r[0] = a[0] * b[0] - a.tail<3>().dot(b.tail<3>());
    r.tail<3>() = a[0] * b.tail<3>() + b[0] * a.tail<3>() + a.tail<3>().cross(b.tail<3>());
    return r;
}

// Rotate Euler parameters by a body-frame rotation vector phi_bar (exponential map):
// A(p_new) = A(p) exp(skew(phi_bar)). Keeps |p| = 1 exactly up to round-off.
inline Vec4 rotate_euler_parameters_body(const Vec4& p, const Vec3& phi_bar) {
    const double angle = phi_bar.norm();
    Vec4 dq;
    if (angle < 1e-12) {
        dq << 1.0, 0.5 * phi_bar;
    } else {
        dq << std::cos(angle / 2), std::sin(angle / 2) * phi_bar / angle;
    }
    Vec4 out = quaternion_product(p, dq);
    return out / out.norm();
}

// A unit vector perpendicular to a (deterministic), for building joint frames.
inline Vec3 any_perpendicular(const Vec3& a) {
    const Vec3 n = a.normalized();
    Vec3 trial = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return (trial - trial.dot(n) * n).normalized();
}

// Wrap an angle to (-pi, pi].
inline double wrap_angle(double a) {
    const double two_pi = 2.0 * M_PI;
    a = std::fmod(a + M_PI, two_pi);
    if (a <= 0) a += two_pi;
    return a - M_PI;
}

}  // namespace mbd
