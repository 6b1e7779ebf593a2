// Force plugins and time functions: book values (Ex. 5.5 with the digest's
// corrected numbers, Ex. 7.7), exact Jacobians against central finite
// differences, Q = -dV/dq for conservative elements, and time-function
// derivatives. The plugins are created through the registry from the build
// tree, with hand-built ForceSpecs.
#include "support/input_files.hpp"
#include "support/test_paths.hpp"
#include <mbd/registry.hpp>
#include <mbd/sdk/force.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/time_function.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace mbd {
namespace {

// ---------------------------------------------------------------- Param trees
Param num(double v) {
    Param p;
    p.kind = Param::Kind::Scalar;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    p.text = buf;
    p.file = "test.yaml";
    p.line = 1;
    return p;
}
Param word(const std::string& s) {
    Param p;
    p.text = s;
    p.file = "test.yaml";
    p.line = 1;
    return p;
}
Param list(std::vector<Param> items) {
    Param p;
    p.kind = Param::Kind::List;
    p.items = std::move(items);
    p.file = "test.yaml";
    p.line = 1;
    return p;
}
Param nums(std::initializer_list<double> values) {
    std::vector<Param> items;
    for (double v : values) items.push_back(num(v));
    return list(items);
}
Param map(std::vector<std::pair<std::string, Param>> fields) {
    Param p;
    p.kind = Param::Kind::Map;
    for (auto& kv : fields) p.fields[kv.first] = kv.second;
    p.file = "test.yaml";
    p.line = 7;
    return p;
}

Registry& registry() {
    static Registry r({std::filesystem::path(MBD_BUILD_DIR) / "lib/mbd/plugins"});
    return r;
}

// A ForceSpec whose Params point at a node it owns (kept at a stable address).
struct SpecHolder {
    Param node;
    ForceSpec spec;
};
std::unique_ptr<SpecHolder> make_spec(const std::string& type, Dimension dim, Param params) {
    auto h = std::make_unique<SpecHolder>();
    h->node = std::move(params);
    h->spec.name = "f1";
    h->spec.type = type;
    h->spec.dimension = dim;
    h->spec.params = Params("force 'f1'", &h->node);
    return h;
}

BodyInfo planar_info(const std::string& name, double mass, const Vec2& R, double theta) {
    BodyInfo b;
    b.name = name;
    b.mass = mass;
    b.position << R, 0.0;
    b.angle = theta;
    b.orientation = Eigen::AngleAxisd(theta, Vec3::UnitZ()).toRotationMatrix();
    return b;
}
BodyInfo spatial_info(const std::string& name, double mass, const Vec3& R, const Mat3& A) {
    BodyInfo b;
    b.name = name;
    b.mass = mass;
    b.position = R;
    b.orientation = A;
    return b;
}
Marker marker(const Vec3& u, const Mat3& A_bar = Mat3::Identity(), double angle = 0.0) {
    Marker m;
    m.u_bar = u;
    m.A_bar = A_bar;
    m.angle = angle;
    return m;
}

// ---------------------------------------------------------------- body states
struct States {
    std::vector<PlanarBody> planar;
    std::vector<SpatialBody> spatial;
    double t = 0.0;

    Dimension dim() const { return planar.empty() ? Dimension::Spatial : Dimension::Planar; }
    int nv() const { return velocities_per_body(dim()); }
    int n() const { return nv() * static_cast<int>(planar.empty() ? spatial.size() : planar.size()); }
    BodyStates view() const {
        BodyStates b;
        b.t = t;
        for (const auto& p : planar) b.planar_bodies.push_back(&p);
        for (const auto& s : spatial) b.spatial_bodies.push_back(&s);
        return b;
    }
    // Position increment of velocity-like coordinate `col` (architecture.md: spatial
    // rotations are body-frame rotation vectors applied with the exponential map).
    States moved(int col, double h) const {
        States s = *this;
        const int k = col / nv(), c = col % nv();
        if (dim() == Dimension::Planar) {
            PlanarBody& b = s.planar[k];
            Vec2 R = b.R;
            double th = b.theta;
            if (c < 2) R[c] += h; else th += h;
            b.set(R, th, b.Rdot, b.omega);
        } else {
            SpatialBody& b = s.spatial[k];
            Vec3 R = b.R;
            Vec4 p = b.p;
            if (c < 3) R[c] += h; else p = rotate_euler_parameters_body(p, h * Vec3::Unit(c - 3));
            b.set(R, p, b.Rdot, b.omega_bar);
        }
        return s;
    }
    States sped(int col, double h) const {
        States s = *this;
        const int k = col / nv(), c = col % nv();
        if (dim() == Dimension::Planar) {
            PlanarBody& b = s.planar[k];
            Vec2 Rd = b.Rdot;
            double w = b.omega;
            if (c < 2) Rd[c] += h; else w += h;
            b.set(b.R, b.theta, Rd, w);
        } else {
            SpatialBody& b = s.spatial[k];
            Vec3 Rd = b.Rdot, w = b.omega_bar;
            if (c < 3) Rd[c] += h; else w[c - 3] += h;
            b.set(b.R, b.p, Rd, w);
        }
        return s;
    }
};

Eigen::VectorXd force_vector(const Force& f, const States& s) {
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(s.n());
    f.evaluate(s.view(), Q);
    return Q;
}

Mat3 random_rotation(std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    return rotation_from_euler_parameters(Vec4(g(rng), g(rng), g(rng), g(rng)).normalized());
}
Vec3 random_vec(std::mt19937& rng, double scale = 1.0) {
    std::uniform_real_distribution<double> u(-scale, scale);
    return Vec3(u(rng), u(rng), u(rng));
}
PlanarBody planar_body(const Vec2& R, double th, const Vec2& Rd, double w) {
    PlanarBody b;
    b.set(R, th, Rd, w);
    return b;
}
SpatialBody spatial_body(const Vec3& R, const Mat3& A, const Vec3& Rd, const Vec3& wbar) {
    SpatialBody b;
    b.set(R, euler_parameters_from_rotation(A), Rd, wbar);
    return b;
}

// Analytic dQ/dq, dQ/dv against central differences; returns the largest error
// relative to (1 + largest entry).
double jacobian_error(const Force& f, const States& s, double* scale_out = nullptr) {
    const int n = s.n();
    Eigen::MatrixXd Jq = Eigen::MatrixXd::Zero(n, n), Jv = Eigen::MatrixXd::Zero(n, n);
    EXPECT_TRUE(f.has_jacobians());
    f.jacobians(s.view(), Jq, Jv);
    Eigen::MatrixXd Fq(n, n), Fv(n, n);
    const double h = 1e-6;
    for (int c = 0; c < n; ++c) {
        Fq.col(c) = (force_vector(f, s.moved(c, h)) - force_vector(f, s.moved(c, -h))) / (2 * h);
        Fv.col(c) = (force_vector(f, s.sped(c, h)) - force_vector(f, s.sped(c, -h))) / (2 * h);
    }
    const double scale = 1.0 + std::max(Fq.cwiseAbs().maxCoeff(), Fv.cwiseAbs().maxCoeff());
    if (scale_out) *scale_out = scale;
    return std::max((Jq - Fq).cwiseAbs().maxCoeff(), (Jv - Fv).cwiseAbs().maxCoeff()) / scale;
}

// max |Q + dV/dq| / (1 + max |Q|), dV/dq by central differences.
double conservative_error(const Force& f, const States& s) {
    EXPECT_TRUE(f.is_conservative());
    const Eigen::VectorXd Q = force_vector(f, s);
    const double h = 1e-6;
    double err = 0.0;
    for (int c = 0; c < s.n(); ++c) {
        const double dV = (f.potential_energy(s.moved(c, h).view()) - f.potential_energy(s.moved(c, -h).view())) / (2 * h);
        err = std::max(err, std::abs(Q[c] + dV));
    }
    return err / (1.0 + Q.cwiseAbs().maxCoeff());
}

// Two moving bodies in a random state, with infos at a nearby "initial" configuration.
struct TwoBodies {
    States s;
    std::vector<BodyInfo> infos;
};
TwoBodies random_planar_pair(std::mt19937& rng) {
    TwoBodies out;
    const Vec3 a = random_vec(rng), b = random_vec(rng);
    out.s.planar.push_back(planar_body(Vec2(0.1, 0.2) + a.head<2>() * 0.1, 0.3 + a.z(), random_vec(rng).head<2>(), a.x() * 3));
    out.s.planar.push_back(planar_body(Vec2(1.1, -0.4) + b.head<2>() * 0.1, -0.7 + b.z(), random_vec(rng).head<2>(), b.y() * 3));
    out.s.t = 0.37;
    out.infos = {planar_info("a", 2.0, Vec2(0.1, 0.2), 0.3), planar_info("b", 3.0, Vec2(1.1, -0.4), -0.7)};
    return out;
}
TwoBodies random_spatial_pair(std::mt19937& rng, const Mat3& Ai, const Mat3& Aj) {
    TwoBodies out;
    out.s.spatial.push_back(spatial_body(Vec3(0.1, 0.2, 0.3) + random_vec(rng, 0.1), Ai, random_vec(rng), random_vec(rng, 3)));
    out.s.spatial.push_back(spatial_body(Vec3(0.9, -0.4, 0.5) + random_vec(rng, 0.1), Aj, random_vec(rng), random_vec(rng, 3)));
    out.s.t = 0.37;
    out.infos = {spatial_info("a", 2.0, Vec3(0.1, 0.2, 0.3), Ai), spatial_info("b", 3.0, Vec3(0.9, -0.4, 0.5), Aj)};
    return out;
}

// ======================================================== book Ex. 5.5 (TSDA)
TEST(SpringDamper, BookExample5_5FourBarWithCorrectedValues) {
    // Four-bar: crank 2 (l = 0.2) pinned at O = (0, 0), coupler 3 (l = 0.4), rocker 4
    // (l = 0.3) pinned at C = (0.35, 0); body frames at link centres. theta2 = 70 deg,
    // theta2dot = 150 rad/s. Loop closure solved here (circle intersection).
    const double l2 = 0.2, l3 = 0.4, l4 = 0.3, th2 = 70.0 * M_PI / 180.0, w2 = 150.0;
    const Vec2 O(0, 0), C(0.35, 0);
    const Vec2 e2(std::cos(th2), std::sin(th2));
    const Vec2 A = O + l2 * e2;
    const Vec2 d = C - A;
    const double D = d.norm(), a = (l3 * l3 - l4 * l4 + D * D) / (2 * D), h = std::sqrt(l3 * l3 - a * a);
    const Vec2 B = A + a * d / D + h * perp(d / D);
    const double th3 = std::atan2(B.y() - A.y(), B.x() - A.x());
    const double th4 = std::atan2(C.y() - B.y(), C.x() - B.x()) + 2 * M_PI;  // rocker axis from B to C
    EXPECT_NEAR(th3 * 180 / M_PI, 13.3085, 1e-4);
    EXPECT_NEAR(th4 * 180 / M_PI, 248.9690, 1e-4);
    // Velocity closure: l2 w2 perp(e2) + l3 w3 perp(e3) + l4 w4 perp(e4) = 0 (B -> C vector l4 e4).
    const Vec2 e3(std::cos(th3), std::sin(th3)), e4(std::cos(th4), std::sin(th4));
    Mat2 M;
    M.col(0) = l3 * perp(e3);
    M.col(1) = l4 * perp(e4);
    const Vec2 w34 = M.colPivHouseholderQr().solve(-l2 * w2 * perp(e2));
    EXPECT_NEAR(w34[0], 1.63438, 1e-4);
    EXPECT_NEAR(w34[1], 101.2131, 1e-3);

    States s;
    // body 2: centre at l2/2 e2; body 4: centre at C - l4/2 e4
    s.planar.push_back(planar_body(O + 0.5 * l2 * e2, th2, 0.5 * l2 * w2 * perp(e2), w2));
    s.planar.push_back(planar_body(C - 0.5 * l4 * e4, th4, -0.5 * l4 * w34[1] * perp(e4), w34[1]));
    // the book's qdot = [-14.0954, 5.1303, 150, -14.1706, 5.4481, 101.212]
    EXPECT_NEAR(s.planar[0].Rdot.x(), -14.0954, 1e-4);
    EXPECT_NEAR(s.planar[1].Rdot.y(), 5.4481, 1e-3);

    auto h5 = make_spec("spring_damper", Dimension::Planar,
                        map({{"stiffness", num(250)}, {"damping", num(10)}, {"rest_length", num(0.35)}}));
    h5->spec.bodies = {planar_info("crank", 1, s.planar[0].R, th2), planar_info("rocker", 1, s.planar[1].R, th4)};
    h5->spec.markers = {marker(Vec3(0.03, 0, 0)), marker(Vec3(-0.05, 0, 0))};
    auto force = registry().create_force(h5->spec, "test");
    const Eigen::VectorXd Q = force_vector(*force, s);
    const double expected[6] = {3.52877, 0.60339, -0.09329, -3.52877, -0.60339, 0.15386};
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(Q[k], expected[k], 1e-4 * std::abs(expected[k]) + 5e-6) << "Q[" << k << "]";
    EXPECT_NEAR(Q.head<2>().norm(), 3.57999, 1e-4 * 3.58);  // f_s
    EXPECT_FALSE(force->is_conservative());
    EXPECT_LT(jacobian_error(*force, s), 1e-7);
}

// ======================================================== Jacobians (FD)
TEST(ForceJacobians, SpringDamperPlanarAndSpatial) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 5; ++trial) {
        TwoBodies tb = random_planar_pair(rng);
        auto h = make_spec("spring_damper", Dimension::Planar,
                           map({{"stiffness", num(300)}, {"damping", num(7)},
                                {"force", map({{"type", word("harmonic")}, {"amplitude", num(2)}, {"frequency", num(3)}})}}));
        h->spec.bodies = tb.infos;
        h->spec.markers = {marker(Vec3(0.2, -0.1, 0)), marker(Vec3(-0.3, 0.05, 0))};
        auto f = registry().create_force(h->spec, "test");
        EXPECT_LT(jacobian_error(*f, tb.s), 1e-7) << "planar trial " << trial;

        TwoBodies sb = random_spatial_pair(rng, random_rotation(rng), random_rotation(rng));
        auto hs = make_spec("spring_damper", Dimension::Spatial,
                            map({{"stiffness", num(300)}, {"damping", num(7)}, {"rest_length", num(0.5)}, {"force", num(1.5)}}));
        hs->spec.bodies = sb.infos;
        hs->spec.markers = {marker(random_vec(rng, 0.3)), marker(random_vec(rng, 0.3))};
        auto fs = registry().create_force(hs->spec, "test");
        EXPECT_LT(jacobian_error(*fs, sb.s), 1e-7) << "spatial trial " << trial;
    }
}

TEST(ForceJacobians, RotationalSpringDamperPlanarAndSpatial) {
    std::mt19937 rng(12);
    for (int trial = 0; trial < 5; ++trial) {
        TwoBodies tb = random_planar_pair(rng);
        auto h = make_spec("rotational_spring_damper", Dimension::Planar,
                           map({{"stiffness", num(40)}, {"damping", num(3)}, {"torque", num(0.5)}}));
        h->spec.bodies = tb.infos;
        auto f = registry().create_force(h->spec, "test");
        EXPECT_LT(jacobian_error(*f, tb.s), 1e-7) << "planar trial " << trial;

        // Marker frames with a common z at t = 0; the state turns body j about that axis
        // by a moderate angle and tilts it a little (the axes then no longer coincide).
        const Mat3 Ai = random_rotation(rng), Abar_i = random_rotation(rng), Abar_j = random_rotation(rng);
        const Mat3 Aj0 = Ai * Abar_i * Abar_j.transpose();
        const Mat3 Aj = Ai * Abar_i * Eigen::AngleAxisd(0.8, Vec3::UnitZ()).toRotationMatrix() *
                        Eigen::AngleAxisd(0.1, random_vec(rng).normalized()).toRotationMatrix() * Abar_j.transpose();
        TwoBodies sb = random_spatial_pair(rng, Ai, Aj);
        sb.infos[1].orientation = Aj0;
        auto hs = make_spec("rotational_spring_damper", Dimension::Spatial,
                            map({{"stiffness", num(40)}, {"damping", num(3)}, {"torque", num(0.5)}}));
        hs->spec.bodies = sb.infos;
        hs->spec.markers = {marker(Vec3::Zero(), Abar_i), marker(Vec3::Zero(), Abar_j)};
        auto fs = registry().create_force(hs->spec, "test");
        EXPECT_LT(jacobian_error(*fs, sb.s), 1e-7) << "spatial trial " << trial;
    }
}

TEST(ForceJacobians, BushingPlanarAndSpatial) {
    std::mt19937 rng(13);
    for (int trial = 0; trial < 5; ++trial) {
        TwoBodies tb = random_planar_pair(rng);
        auto h = make_spec("bushing", Dimension::Planar,
                           map({{"stiffness", nums({1000, 2000, 50})}, {"damping", nums({10, 20, 1})}}));
        h->spec.bodies = tb.infos;
        h->spec.markers = {marker(Vec3(0.5, -0.3, 0), Mat3::Identity(), 0.4), marker(Vec3(-0.5, 0.3, 0), Mat3::Identity(), 1.1)};
        auto f = registry().create_force(h->spec, "test");
        EXPECT_LT(jacobian_error(*f, tb.s), 1e-7) << "planar trial " << trial;

        const Mat3 Ai = random_rotation(rng), Abar_i = random_rotation(rng), Abar_j = random_rotation(rng);
        const Mat3 rel = Eigen::AngleAxisd(0.2 + 0.5 * trial, random_vec(rng).normalized()).toRotationMatrix();
        const Mat3 Aj = Ai * Abar_i * rel * Abar_j.transpose();
        TwoBodies sb = random_spatial_pair(rng, Ai, Aj);
        auto hs = make_spec("bushing", Dimension::Spatial,
                            map({{"stiffness", nums({1000, 2000, 3000, 50, 60, 70})},
                                 {"damping", nums({10, 20, 30, 1, 2, 3})}}));
        hs->spec.bodies = sb.infos;
        hs->spec.markers = {marker(random_vec(rng, 0.3), Abar_i), marker(random_vec(rng, 0.3), Abar_j)};
        auto fs = registry().create_force(hs->spec, "test");
        EXPECT_LT(jacobian_error(*fs, sb.s), 1e-7) << "spatial trial " << trial;
    }
}

TEST(ForceJacobians, PointForceAndTorqueInBodyFrame) {
    std::mt19937 rng(14);
    States s;
    s.spatial.push_back(spatial_body(random_vec(rng), random_rotation(rng), random_vec(rng), random_vec(rng)));
    for (const char* frame : {"world", "body"}) {
        auto h = make_spec("point_force", Dimension::Spatial,
                           map({{"force", nums({5, 0, -3})}, {"frame", word(frame)}}));
        h->spec.bodies = {spatial_info("b", 1, s.spatial[0].R, s.spatial[0].A)};
        h->spec.markers = {marker(Vec3(0.2, 0, -0.15))};
        EXPECT_LT(jacobian_error(*registry().create_force(h->spec, "test"), s), 1e-7) << frame;
        auto t = make_spec("point_torque", Dimension::Spatial, map({{"torque", nums({1, 2, 3})}, {"frame", word(frame)}}));
        t->spec.bodies = h->spec.bodies;
        EXPECT_LT(jacobian_error(*registry().create_force(t->spec, "test"), s), 1e-7) << frame;
    }
}

// ======================================================== conservative forces
TEST(ConservativeForces, GeneralizedForceIsMinusGradientOfPotential) {
    std::mt19937 rng(21);
    // gravity, planar and spatial
    {
        TwoBodies tb = random_planar_pair(rng);
        auto h = make_spec("gravity", Dimension::Planar, map({}));
        h->spec.bodies = tb.infos;
        h->spec.gravity = Vec3(0.5, -9.81, 0);
        auto f = registry().create_force(h->spec, "test");
        EXPECT_LT(conservative_error(*f, tb.s), 1e-8);
        const Eigen::VectorXd Q = force_vector(*f, tb.s);
        EXPECT_NEAR(Q[1], -9.81 * 2.0, 1e-12);  // m g on body a (mass 2)
        EXPECT_NEAR(Q[2], 0.0, 0.0);
        TwoBodies sb = random_spatial_pair(rng, random_rotation(rng), random_rotation(rng));
        auto hs = make_spec("gravity", Dimension::Spatial, map({}));
        hs->spec.bodies = sb.infos;
        hs->spec.gravity = Vec3(0, 0, -9.81);
        auto fs = registry().create_force(hs->spec, "test");
        EXPECT_LT(conservative_error(*fs, sb.s), 1e-8);
        EXPECT_NEAR(force_vector(*fs, sb.s)[8], -9.81 * 3.0, 1e-12);
        EXPECT_LT(jacobian_error(*fs, sb.s), 1e-9);
    }
    for (int trial = 0; trial < 3; ++trial) {
        TwoBodies tb = random_planar_pair(rng);
        TwoBodies sb = random_spatial_pair(rng, random_rotation(rng), random_rotation(rng));
        {
            auto h = make_spec("spring_damper", Dimension::Planar, map({{"stiffness", num(300)}, {"rest_length", num(0.4)}}));
            h->spec.bodies = tb.infos;
            h->spec.markers = {marker(Vec3(0.2, -0.1, 0)), marker(Vec3(-0.3, 0.05, 0))};
            EXPECT_LT(conservative_error(*registry().create_force(h->spec, "test"), tb.s), 1e-7);
            auto hs = make_spec("spring_damper", Dimension::Spatial, map({{"stiffness", num(300)}}));
            hs->spec.bodies = sb.infos;
            hs->spec.markers = {marker(Vec3(0.1, 0.2, 0.3)), marker(Vec3(-0.2, 0.1, 0))};
            EXPECT_LT(conservative_error(*registry().create_force(hs->spec, "test"), sb.s), 1e-7);
        }
        {
            auto h = make_spec("rotational_spring_damper", Dimension::Planar, map({{"stiffness", num(40)}}));
            h->spec.bodies = tb.infos;
            EXPECT_LT(conservative_error(*registry().create_force(h->spec, "test"), tb.s), 1e-7);
            const Mat3 Abar_i = random_rotation(rng), Abar_j = random_rotation(rng);
            const Mat3 Ai = sb.s.spatial[0].A;
            const Mat3 Aj = Ai * Abar_i * Eigen::AngleAxisd(-0.6, Vec3::UnitZ()).toRotationMatrix() *
                            Eigen::AngleAxisd(0.2, random_vec(rng).normalized()).toRotationMatrix() * Abar_j.transpose();
            States s2 = sb.s;
            s2.spatial[1] = spatial_body(sb.s.spatial[1].R, Aj, sb.s.spatial[1].Rdot, sb.s.spatial[1].omega_bar);
            auto hs = make_spec("rotational_spring_damper", Dimension::Spatial, map({{"stiffness", num(40)}, {"rest_angle", num(0.1)}}));
            hs->spec.bodies = sb.infos;
            hs->spec.markers = {marker(Vec3::Zero(), Abar_i), marker(Vec3::Zero(), Abar_j)};
            EXPECT_LT(conservative_error(*registry().create_force(hs->spec, "test"), s2), 1e-7);
        }
        {
            auto h = make_spec("bushing", Dimension::Planar, map({{"stiffness", nums({1000, 2000, 50})}}));
            h->spec.bodies = tb.infos;
            h->spec.markers = {marker(Vec3(0.5, -0.3, 0), Mat3::Identity(), 0.4), marker(Vec3(-0.5, 0.3, 0), Mat3::Identity(), 1.1)};
            EXPECT_LT(conservative_error(*registry().create_force(h->spec, "test"), tb.s), 1e-7);
            const Mat3 Abar_i = random_rotation(rng), Abar_j = random_rotation(rng);
            const Mat3 Ai = sb.s.spatial[0].A;
            const Mat3 Aj = Ai * Abar_i * Eigen::AngleAxisd(1.0 + trial, random_vec(rng).normalized()).toRotationMatrix() * Abar_j.transpose();
            States s2 = sb.s;
            s2.spatial[1] = spatial_body(sb.s.spatial[1].R, Aj, sb.s.spatial[1].Rdot, sb.s.spatial[1].omega_bar);
            auto hs = make_spec("bushing", Dimension::Spatial, map({{"stiffness", nums({1000, 2000, 3000, 50, 60, 70})}}));
            hs->spec.bodies = sb.infos;
            hs->spec.markers = {marker(Vec3(0.1, 0, 0.2), Abar_i), marker(Vec3(0, -0.2, 0.1), Abar_j)};
            EXPECT_LT(conservative_error(*registry().create_force(hs->spec, "test"), s2), 1e-7);
        }
    }
}

TEST(ConservativeForces, DampingOrActuationIsNotConservative) {
    TwoBodies tb;
    std::mt19937 rng(3);
    tb = random_planar_pair(rng);
    auto h = make_spec("spring_damper", Dimension::Planar, map({{"stiffness", num(1)}, {"damping", num(0.1)}}));
    h->spec.bodies = tb.infos;
    EXPECT_FALSE(registry().create_force(h->spec, "test")->is_conservative());
    auto a = make_spec("rotational_spring_damper", Dimension::Planar, map({{"stiffness", num(1)}, {"torque", num(2)}}));
    a->spec.bodies = tb.infos;
    EXPECT_FALSE(registry().create_force(a->spec, "test")->is_conservative());
    // default rest length = the initial distance of the (mass-centre) points
    auto r = make_spec("spring_damper", Dimension::Planar, map({{"stiffness", num(100)}}));
    r->spec.bodies = tb.infos;
    States s0;
    s0.planar.push_back(planar_body(tb.infos[0].position.head<2>(), tb.infos[0].angle, Vec2(1, 2), 3));
    s0.planar.push_back(planar_body(tb.infos[1].position.head<2>(), tb.infos[1].angle, Vec2(0, 0), 0));
    auto rf = registry().create_force(r->spec, "test");
    EXPECT_NEAR(force_vector(*rf, s0).norm(), 0.0, 1e-12);
    EXPECT_NEAR(rf->potential_energy(s0.view()), 0.0, 1e-15);
}

// A constant force in world axes is a dead load: V = -F . r_P with r_P = R + A u_bar_P, written
// here from the body's pose; its gradient is -Q by central differences (the moment arm's change
// included). A follower force (frame: body) or a time-varying one has no potential.
TEST(ConservativeForces, ADeadPointLoadIsMinusTheGradientOfMinusFDotRp) {
    std::mt19937 rng(41);
    for (int trial = 0; trial < 3; ++trial) {
        TwoBodies tb = random_planar_pair(rng);
        States planar;
        planar.planar.push_back(tb.s.planar[0]);
        const Vec3 u(0.3, -0.2, 0.0);
        auto h = make_spec("point_force", Dimension::Planar, map({{"force", nums({4.0, -7.0})}}));
        h->spec.bodies = {tb.infos[0]};
        h->spec.markers = {marker(u)};
        auto f = registry().create_force(h->spec, "test");
        EXPECT_LT(conservative_error(*f, planar), 1e-9) << trial;
        const PlanarBody& b = planar.planar[0];
        const Vec2 rP = b.R + planar_rotation(b.theta) * u.head<2>();
        EXPECT_NEAR(f->potential_energy(planar.view()), -(4.0 * rP.x() - 7.0 * rP.y()), 1e-12);

        TwoBodies sb = random_spatial_pair(rng, random_rotation(rng), random_rotation(rng));
        States spatial;
        spatial.spatial.push_back(sb.s.spatial[0]);
        const Vec3 us(0.2, 0.1, -0.35), F(5.0, -2.0, 3.0);
        auto hs = make_spec("point_force", Dimension::Spatial,
                            map({{"force", list({num(5.0), map({{"type", word("constant")}, {"value", num(-2.0)}}), num(3.0)})}}));
        hs->spec.bodies = {sb.infos[0]};
        hs->spec.markers = {marker(us)};
        auto fs = registry().create_force(hs->spec, "test");
        EXPECT_LT(conservative_error(*fs, spatial), 1e-9) << trial;
        const SpatialBody& c = spatial.spatial[0];
        EXPECT_NEAR(fs->potential_energy(spatial.view()), -F.dot(c.R + c.A * us), 1e-12);
    }
    States s;
    s.planar.push_back(planar_body(Vec2(1, 1), 0.4, Vec2::Zero(), 0));
    const std::vector<BodyInfo> body = {planar_info("b", 1, Vec2(1, 1), 0.4)};
    auto follower = make_spec("point_force", Dimension::Planar, map({{"force", nums({1.0, 2.0})}, {"frame", word("body")}}));
    auto varying = make_spec("point_force", Dimension::Planar,
                             map({{"force", list({num(0), map({{"type", word("linear")}, {"initial", num(1)}, {"rate", num(2)}})})}}));
    for (auto* spec : {follower.get(), varying.get()}) {
        spec->spec.bodies = body;
        auto f = registry().create_force(spec->spec, "test");
        EXPECT_FALSE(f->is_conservative());
        EXPECT_EQ(f->potential_energy(s.view()), 0.0);
    }
}

// Damping oracle: at a configuration where the spring is undeformed, a damper
// with coefficient c gives the same generalized force as the time derivative,
// along the motion, of a spring with stiffness c (the terms that multiply the
// deformation vanish there). The derivative is taken by central differences of
// the stiffness-only element along q(t) = q + v t (exponential map for rotations).
States advanced(const States& s, double dt) {
    States out = s;
    for (auto& b : out.planar) b.set(b.R + dt * b.Rdot, b.theta + dt * b.omega, b.Rdot, b.omega);
    for (auto& b : out.spatial) b.set(b.R + dt * b.Rdot, rotate_euler_parameters_body(b.p, dt * b.omega_bar), b.Rdot, b.omega_bar);
    return out;
}
double damping_error(const std::string& type, const States& s, const std::vector<BodyInfo>& infos,
                     const std::vector<Marker>& markers, std::vector<std::pair<std::string, Param>> stiff,
                     std::vector<std::pair<std::string, Param>> damp) {
    auto hk = make_spec(type, s.dim(), map(std::move(stiff)));
    auto hc = make_spec(type, s.dim(), map(std::move(damp)));
    hk->spec.bodies = hc->spec.bodies = infos;
    hk->spec.markers = hc->spec.markers = markers;
    auto fk = registry().create_force(hk->spec, "test");
    auto fc = registry().create_force(hc->spec, "test");
    EXPECT_LT(force_vector(*fk, s).norm(), 1e-12) << type << ": the spring should be undeformed";
    const double dt = 1e-6;
    const Eigen::VectorXd rate = (force_vector(*fk, advanced(s, dt)) - force_vector(*fk, advanced(s, -dt))) / (2 * dt);
    const Eigen::VectorXd Qc = force_vector(*fc, s);
    EXPECT_GT(Qc.norm(), 1e-3) << type;
    return (Qc - rate).cwiseAbs().maxCoeff() / (1.0 + Qc.cwiseAbs().maxCoeff());
}

TEST(Damping, DamperForceIsTheRateOfAnUndeformedSpringsForce) {
    std::mt19937 rng(31);
    for (int trial = 0; trial < 3; ++trial) {
        // planar
        TwoBodies tb = random_planar_pair(rng);
        for (int k = 0; k < 2; ++k) tb.infos[k] = planar_info(tb.infos[k].name, 1, tb.s.planar[k].R, tb.s.planar[k].theta);
        const Vec3 ui(0.2, -0.1, 0), uj(-0.3, 0.05, 0);
        const double l = (tb.s.planar[0].point(ui.head<2>()) - tb.s.planar[1].point(uj.head<2>())).norm();
        EXPECT_LT(damping_error("spring_damper", tb.s, tb.infos, {marker(ui), marker(uj)},
                                {{"stiffness", num(7)}, {"rest_length", num(l)}},
                                {{"stiffness", num(0)}, {"damping", num(7)}, {"rest_length", num(l)}}), 1e-7);
        EXPECT_LT(damping_error("rotational_spring_damper", tb.s, tb.infos, {}, {{"stiffness", num(7)}},
                                {{"stiffness", num(0)}, {"damping", num(7)}}), 1e-7);
        {
            // planar bushing markers coinciding now: origin P, x axis at angle 0.3 (world)
            const Vec2 P(0.4, 0.1);
            std::vector<Marker> m;
            for (int k = 0; k < 2; ++k) {
                const PlanarBody& b = tb.s.planar[k];
                Vec3 u = Vec3::Zero();
                u.head<2>() = b.A.transpose() * (P - b.R);
                m.push_back(marker(u, Mat3::Identity(), 0.3 - b.theta));
            }
            EXPECT_LT(damping_error("bushing", tb.s, tb.infos, m, {{"stiffness", nums({5, 6, 7})}},
                                    {{"stiffness", nums({0, 0, 0})}, {"damping", nums({5, 6, 7})}}), 1e-7);
        }
        // spatial
        TwoBodies sb = random_spatial_pair(rng, random_rotation(rng), random_rotation(rng));
        for (int k = 0; k < 2; ++k) sb.infos[k] = spatial_info(sb.infos[k].name, 1, sb.s.spatial[k].R, sb.s.spatial[k].A);
        const Vec3 si(0.1, 0.2, 0.3), sj(-0.2, 0.1, 0);
        const double ls = (sb.s.spatial[0].point(si) - sb.s.spatial[1].point(sj)).norm();
        EXPECT_LT(damping_error("spring_damper", sb.s, sb.infos, {marker(si), marker(sj)},
                                {{"stiffness", num(7)}, {"rest_length", num(ls)}},
                                {{"stiffness", num(0)}, {"damping", num(7)}, {"rest_length", num(ls)}}), 1e-7);
        // marker frames coinciding now (world frame F at point P)
        const Mat3 F = random_rotation(rng);
        const Vec3 P = random_vec(rng);
        std::vector<Marker> m;
        for (int k = 0; k < 2; ++k) {
            const SpatialBody& b = sb.s.spatial[k];
            m.push_back(marker(b.A.transpose() * (P - b.R), b.A.transpose() * F));
        }
        EXPECT_LT(damping_error("rotational_spring_damper", sb.s, sb.infos, m, {{"stiffness", num(7)}},
                                {{"stiffness", num(0)}, {"damping", num(7)}}), 1e-7);
        EXPECT_LT(damping_error("bushing", sb.s, sb.infos, m, {{"stiffness", nums({1, 2, 3, 4, 5, 6})}},
                                {{"stiffness", nums({0, 0, 0, 0, 0, 0})}, {"damping", nums({1, 2, 3, 4, 5, 6})}}), 1e-7);
    }
}

// ======================================================== point force, book Ex. 7.7
TEST(PointForce, BookExample7_7) {
    const double phi = M_PI / 4, theta = M_PI / 2, psi = 0.0;  // Euler angles 3-1-3
    const Mat3 A = (Eigen::AngleAxisd(phi, Vec3::UnitZ()) * Eigen::AngleAxisd(theta, Vec3::UnitX()) *
                    Eigen::AngleAxisd(psi, Vec3::UnitZ()))
                       .toRotationMatrix();
    States s;
    s.spatial.push_back(spatial_body(Vec3(1, 2, 3), A, Vec3::Zero(), Vec3::Zero()));
    const Vec3 u_bar(0.2, 0, -0.15), F(5, 0, -3);
    const Vec3 uP = s.spatial[0].A * u_bar;
    EXPECT_NEAR(uP.x(), 0.0354, 1e-4);
    EXPECT_NEAR(uP.y(), 0.2475, 1e-4);
    EXPECT_NEAR(uP.z(), 0.0, 1e-12);

    auto h = make_spec("point_force", Dimension::Spatial, map({{"force", nums({5, 0, -3})}}));
    h->spec.bodies = {spatial_info("body", 1, Vec3(1, 2, 3), A)};
    h->spec.markers = {marker(u_bar)};
    auto f = registry().create_force(h->spec, "test");
    const Eigen::VectorXd Q = force_vector(*f, s);
    EXPECT_LT((Q.head<3>() - F).norm(), 1e-12);
    const Vec3 moment = s.spatial[0].A * Q.tail<3>();
    const Vec3 book(-0.7425, 0.1061, -1.2375);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(moment[k], book[k], 1e-4) << k;
    // The book's Euler-angle form Q_theta = G^T (u_P x F) = [-1.2375, -0.45, -0.6] (Eq. 7.115)
    Mat3 G;
    G << 0, std::cos(phi), std::sin(theta) * std::sin(phi), 0, std::sin(phi), -std::sin(theta) * std::cos(phi), 1, 0,
        std::cos(theta);
    const Vec3 Qtheta = G.transpose() * moment;
    EXPECT_NEAR(Qtheta[0], -1.2375, 1e-4);
    EXPECT_NEAR(Qtheta[1], -0.45, 1e-4);
    EXPECT_NEAR(Qtheta[2], -0.6, 1e-4);

    // The same force given in body axes: F_bar = A^T F.
    const Vec3 Fb = A.transpose() * F;
    auto hb = make_spec("point_force", Dimension::Spatial,
                        map({{"force", nums({Fb.x(), Fb.y(), Fb.z()})}, {"frame", word("body")}}));
    hb->spec.bodies = h->spec.bodies;
    hb->spec.markers = h->spec.markers;
    EXPECT_LT((force_vector(*registry().create_force(hb->spec, "test"), s) - Q).norm(), 1e-12);
}

TEST(PointForce, PlanarMomentArmAndTimeFunctionComponents) {
    States s;
    s.planar.push_back(planar_body(Vec2(1, 1), M_PI / 2, Vec2::Zero(), 0));
    auto h = make_spec("point_force", Dimension::Planar,
                       map({{"force", list({num(0), map({{"type", word("linear")}, {"initial", num(-10)}, {"rate", num(2)}})})}}));
    h->spec.bodies = {planar_info("b", 1, Vec2(1, 1), M_PI / 2)};
    h->spec.markers = {marker(Vec3(0.5, 0, 0))};  // at theta = 90 deg the arm points along +y
    auto f = registry().create_force(h->spec, "test");
    s.t = 1.0;  // F = [0, -8]: arm [0, 0.5] x [0, -8] = 0
    Eigen::VectorXd Q = force_vector(*f, s);
    EXPECT_NEAR(Q[1], -8.0, 1e-12);
    EXPECT_NEAR(Q[2], 0.0, 1e-12);
    s.planar[0].set(Vec2(1, 1), 0.0, Vec2::Zero(), 0);  // arm [0.5, 0]: moment -4
    Q = force_vector(*f, s);
    EXPECT_NEAR(Q[2], -4.0, 1e-12);
    auto t = make_spec("point_torque", Dimension::Planar, map({{"torque", num(2.5)}}));
    t->spec.bodies = h->spec.bodies;
    EXPECT_NEAR(force_vector(*registry().create_force(t->spec, "test"), s)[2], 2.5, 0.0);
}

// ======================================================== input errors

TEST(ForceErrors, ClearMessages) {
    std::mt19937 rng(5);
    TwoBodies tb = random_planar_pair(rng);
    auto neg = make_spec("spring_damper", Dimension::Planar, map({{"stiffness", num(-1)}}));
    neg->spec.bodies = tb.infos;
    std::string m = test::input_error_of([&] { registry().create_force(neg->spec, "test"); });
    EXPECT_NE(m.find("force 'f1'"), std::string::npos) << m;
    EXPECT_NE(m.find("stiffness"), std::string::npos) << m;
    EXPECT_NE(m.find("negative"), std::string::npos) << m;

    auto zero = make_spec("spring_damper", Dimension::Planar, map({{"stiffness", num(1)}}));
    zero->spec.bodies = {tb.infos[0], tb.infos[0]};
    m = test::input_error_of([&] { registry().create_force(zero->spec, "test"); });
    EXPECT_NE(m.find("rest_length"), std::string::npos) << m;

    auto count = make_spec("bushing", Dimension::Spatial, map({{"stiffness", nums({1, 2, 3})}}));
    count->spec.bodies = {spatial_info("a", 1, Vec3::Zero(), Mat3::Identity()), spatial_info("b", 1, Vec3::Zero(), Mat3::Identity())};
    count->spec.markers = {marker(Vec3::Zero()), marker(Vec3::Zero())};
    m = test::input_error_of([&] { registry().create_force(count->spec, "test"); });
    EXPECT_NE(m.find("6 numbers"), std::string::npos) << m;

    auto frame = make_spec("point_force", Dimension::Planar, map({{"force", nums({1, 2})}, {"frame", word("local")}}));
    frame->spec.bodies = {tb.infos[0]};
    m = test::input_error_of([&] { registry().create_force(frame->spec, "test"); });
    EXPECT_NE(m.find("'world' or 'body'"), std::string::npos) << m;

    auto comps = make_spec("point_force", Dimension::Spatial, map({{"force", nums({1, 2})}}));
    comps->spec.bodies = {spatial_info("a", 1, Vec3::Zero(), Mat3::Identity())};
    m = test::input_error_of([&] { registry().create_force(comps->spec, "test"); });
    EXPECT_NE(m.find("3 components"), std::string::npos) << m;
}

// ======================================================== time functions
TimeValue at(const TimeFunction& f, double t) { return f.evaluate(t); }

void check_derivatives(const TimeFunction& f, const std::vector<double>& times, const std::string& label) {
    const double h = 1e-5;
    for (double t : times) {
        const TimeValue v = f.evaluate(t), p = f.evaluate(t + h), m = f.evaluate(t - h);
        const double scale = 1.0 + std::abs(v.f) + std::abs(v.df) + std::abs(v.ddf);
        EXPECT_NEAR(v.df, (p.f - m.f) / (2 * h), 1e-7 * scale) << label << " df at t = " << t;
        EXPECT_NEAR(v.ddf, (p.df - m.df) / (2 * h), 1e-7 * scale) << label << " ddf at t = " << t;
    }
}

TEST(TimeFunctions, DerivativesMatchFiniteDifferences) {
    // away from the spline knots and the step ends, where the third derivative jumps
    const std::vector<double> times = {-0.7, 0.13, 0.37, 0.99, 1.37, 2.2, 2.71, 3.9};
    const std::vector<std::pair<std::string, Param>> cases = {
        {"constant", map({{"type", word("constant")}, {"value", num(3.5)}})},
        {"number", num(-2)},
        {"linear", map({{"type", word("linear")}, {"initial", num(1)}, {"rate", num(-2.5)}})},
        {"polynomial", map({{"type", word("polynomial")}, {"coefficients", nums({1, -2, 0.5, 0.3, -0.1})}})},
        {"harmonic", map({{"type", word("harmonic")}, {"amplitude", num(2)}, {"frequency", num(3)}, {"phase", num(0.4)}, {"offset", num(1)}})},
        {"smooth_step", map({{"type", word("smooth_step")}, {"t0", num(0.2)}, {"t1", num(1.7)}, {"from", num(-1)}, {"to", num(2)}})},
        {"spline", map({{"type", word("spline")}, {"table", list({nums({0, 0}), nums({0.5, 1}), nums({1.2, 0.3}), nums({2, 2}), nums({3, -1})})}})},
    };
    for (const auto& c : cases) check_derivatives(*make_time_function(c.second, "test"), times, c.first);

    // closed forms
    EXPECT_DOUBLE_EQ(at(*make_time_function(cases[1].second, "t"), 5.0).f, -2.0);
    const auto poly = make_time_function(cases[3].second, "t");
    const double t = 1.3;
    EXPECT_NEAR(poly->evaluate(t).f, 1 - 2 * t + 0.5 * t * t + 0.3 * t * t * t - 0.1 * std::pow(t, 4), 1e-14);
    EXPECT_NEAR(poly->evaluate(t).ddf, 1.0 + 1.8 * t - 1.2 * t * t, 1e-13);
    const auto harm = make_time_function(cases[4].second, "t");
    EXPECT_NEAR(harm->evaluate(t).f, 1 + 2 * std::sin(3 * t + 0.4), 1e-14);
    EXPECT_NEAR(harm->evaluate(t).ddf, -18 * std::sin(3 * t + 0.4), 1e-13);
}

TEST(TimeFunctions, SplineInterpolatesItsTableAndIsNatural) {
    const std::vector<std::pair<double, double>> table = {{0, 0}, {0.5, 1}, {1.2, 0.3}, {2, 2}, {3, -1}};
    std::vector<Param> rows;
    for (auto& r : table) rows.push_back(nums({r.first, r.second}));
    const auto s = make_time_function(map({{"type", word("spline")}, {"table", list(rows)}}), "test");
    for (auto& r : table) EXPECT_NEAR(s->evaluate(r.first).f, r.second, 1e-14) << r.first;
    EXPECT_NEAR(s->evaluate(0.0).ddf, 0.0, 1e-12);
    EXPECT_NEAR(s->evaluate(3.0).ddf, 0.0, 1e-12);
    // linear extrapolation with the end slopes
    EXPECT_NEAR(s->evaluate(-1.0).f, -s->evaluate(0.0).df, 1e-12);
    EXPECT_NEAR(s->evaluate(4.0).f, -1.0 + s->evaluate(3.0).df, 1e-12);
    EXPECT_EQ(s->evaluate(5.0).ddf, 0.0);
    // a natural spline reproduces a straight line exactly
    const auto line = make_time_function(
        map({{"type", word("spline")}, {"table", list({nums({0, 1}), nums({0.3, 1.6}), nums({1, 3}), nums({2.5, 6})})}}), "test");
    for (double t : {-1.0, 0.1, 0.77, 1.9, 3.0}) {
        EXPECT_NEAR(line->evaluate(t).f, 1 + 2 * t, 1e-13) << t;
        EXPECT_NEAR(line->evaluate(t).df, 2.0, 1e-13) << t;
    }
    // two points: a straight line
    const auto two = make_time_function(map({{"type", word("spline")}, {"table", list({nums({1, 1}), nums({2, 3})})}}), "t");
    EXPECT_NEAR(two->evaluate(1.25).f, 1.5, 1e-14);
}

TEST(TimeFunctions, SmoothStepEndsWithZeroRate) {
    const auto s = make_time_function(
        map({{"type", word("smooth_step")}, {"t0", num(1)}, {"t1", num(3)}, {"from", num(2)}, {"to", num(-4)}}), "test");
    for (double t : {1.0, 3.0}) {
        const TimeValue v = s->evaluate(t);
        EXPECT_DOUBLE_EQ(v.f, t == 1.0 ? 2.0 : -4.0);
        EXPECT_NEAR(v.df, 0.0, 1e-14);
        EXPECT_NEAR(v.ddf, 0.0, 1e-13);
    }
    EXPECT_NEAR(s->evaluate(2.0).f, -1.0, 1e-14);  // midpoint: h(1/2) = 1/2
    EXPECT_EQ(s->evaluate(0.0).f, 2.0);
    EXPECT_EQ(s->evaluate(10.0).f, -4.0);
    // the rate at the midpoint of the quintic: (to - from) * 15/8 / (t1 - t0)
    EXPECT_NEAR(s->evaluate(2.0).df, -6.0 * 15.0 / 8.0 / 2.0, 1e-13);
}

TEST(TimeFunctions, InputErrors) {
    auto msg = [](const Param& p) { return test::input_error_of([&] { make_time_function(p, "driver 'd1'"); }); };
    std::string m = msg(map({{"value", num(1)}}));
    EXPECT_NE(m.find("needs a 'type'"), std::string::npos) << m;
    EXPECT_NE(m.find("test.yaml:7"), std::string::npos) << m;
    EXPECT_NE(m.find("driver 'd1'"), std::string::npos) << m;
    m = msg(map({{"type", word("sine")}}));
    EXPECT_NE(m.find("unknown time function type 'sine'"), std::string::npos) << m;
    EXPECT_NE(m.find("harmonic"), std::string::npos) << m;
    EXPECT_NE(m.find("smooth_step"), std::string::npos) << m;
    m = msg(map({{"type", word("harmonic")}, {"amplitude", num(1)}, {"frequncy", num(2)}}));
    EXPECT_NE(m.find("unknown key 'frequncy'"), std::string::npos) << m;
    EXPECT_NE(m.find("did you mean 'frequency'"), std::string::npos) << m;
    m = msg(map({{"type", word("constant")}, {"value", num(1)}, {"rate", num(2)}}));  // a misplaced key
    EXPECT_NE(m.find("unknown key 'rate'"), std::string::npos) << m;
    m = msg(map({{"type", word("steps")}, {"table", list({nums({0, 1}), word("x")})}}));
    EXPECT_NE(m.find("row 2 must be a pair"), std::string::npos) << m;
    m = msg(map({{"type", word("constant")}, {"value", word("abc")}}));
    EXPECT_NE(m.find("'value' must be a number"), std::string::npos) << m;
    m = msg(map({{"type", word("spline")}, {"table", list({nums({0, 1}), nums({0, 2})})}}));
    EXPECT_NE(m.find("strictly increasing"), std::string::npos) << m;
    m = msg(map({{"type", word("spline")}, {"table", list({nums({0, 1})})}}));
    EXPECT_NE(m.find("at least 2 points"), std::string::npos) << m;
    m = msg(map({{"type", word("smooth_step")}, {"t0", num(2)}, {"t1", num(2)}, {"to", num(1)}}));
    EXPECT_NE(m.find("greater than t0"), std::string::npos) << m;
    m = msg(map({{"type", word("linear")}}));
    EXPECT_NE(m.find("missing key 'rate'"), std::string::npos) << m;
    m = msg(word("fast"));
    EXPECT_NE(m.find("a number or a map"), std::string::npos) << m;
}

}  // namespace
}  // namespace mbd
