// The spatial ANCF cable (plugins/bodies/ancf ancf_cable_3d*, an `ancf_cable` in a spatial scene)
// against independent oracles: the mass and first moments of the beam, rigid motions that strain
// nothing, finite differences of its own energy, forces and frame, the linear cantilever
// P L^3 / (3 EI) in both transverse directions, the planar element in its plane, a spatial scene
// (free fall, a hinged flexible pendulum keeping its energy), and refusals of bad input.
#include "support/flexible_body.hpp"
#include "support/sampled_run.hpp"

#include <mbd/sdk/body.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace mbd {
namespace {

using test::number_param;
using test::Reduced;

struct Keys {
    std::vector<double> from{0.1, -0.2, 0.3}, to{1.1, 0.5, 0.9};
    int elements = 3;
    double modulus = 1e6, area = 1e-2, second_moment = 1e-6, density = 100;  // EA 1e4, EI 1, rho A 1
    std::vector<double> normal;  // empty: the key left out
    int axial_points = 0;        // 0: the key left out
};

std::map<std::string, Param> fields(const Keys& k) {
    std::map<std::string, Param> f = {{"from", test::list_param(k.from)},
                                      {"to", test::list_param(k.to)},
                                      {"elements", number_param(k.elements)},
                                      {"modulus", number_param(k.modulus)},
                                      {"area", number_param(k.area)},
                                      {"second_moment", number_param(k.second_moment)},
                                      {"density", number_param(k.density)}};
    if (!k.normal.empty()) f["normal"] = test::list_param(k.normal);
    if (k.axial_points) f["axial_points"] = number_param(k.axial_points);
    return f;
}

// An `ancf_cable` made as a scene of `dimension` would make it (test::make_body, spatial or planar).
std::unique_ptr<test::BodyFromKeys> make_cable(const Keys& k, Dimension dimension = Dimension::Spatial) {
    auto b = std::make_unique<test::BodyFromKeys>();
    b->node = test::scalar_param("");
    b->node.kind = Param::Kind::Map;
    b->node.fields = fields(k);
    b->spec = {"beam", "ancf_cable", dimension, Params("body 'beam'", &b->node)};
    b->body = test::shared_registry().create_body(b->spec, "beam.yaml:2");
    return b;
}

double length(const Keys& k) {
    return (Eigen::Vector3d(k.to[0], k.to[1], k.to[2]) - Eigen::Vector3d(k.from[0], k.from[1], k.from[2])).norm();
}

// A deformed configuration: the straight one plus random offsets of size `size`.
Eigen::VectorXd perturbed(const FlexibleBody& body, double size, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss;
    Eigen::VectorXd q = body.initial_coordinates();
    for (int k = 0; k < q.size(); ++k) q[k] += size * gauss(rng);
    return q;
}

// q moved rigidly: positions R r + c, slopes R r'.
Eigen::VectorXd moved(const Eigen::VectorXd& q, const Eigen::Matrix3d& R, const Eigen::Vector3d& c) {
    Eigen::VectorXd out(q.size());
    for (int k = 0; k < q.size(); k += 6) {
        out.segment<3>(k) = R * q.segment<3>(k) + c;
        out.segment<3>(k + 3) = R * q.segment<3>(k + 3);
    }
    return out;
}

// ---------------------------------------------------------------- inertia
TEST(AncfCable3d, MassMatrixGivesTheMassAndFirstMomentsExactly) {
    Keys keys;
    keys.density = 700;  // rho A = 7
    auto c = make_cable(keys);
    const FlexibleBody& body = *c->body;
    const int n = body.coordinates();
    const double L = length(keys), m = 7.0 * L;
    const Eigen::VectorXd q0 = body.initial_coordinates();
    const Eigen::Vector3d centre = 0.5 * (Eigen::Vector3d(0.1, -0.2, 0.3) + Eigen::Vector3d(1.1, 0.5, 0.9));
    Eigen::MatrixXd M;
    body.mass_matrix(q0, M);
    EXPECT_LT((M - M.transpose()).norm(), 1e-15 * M.norm());
    Eigen::VectorXd Q(n);
    for (int d = 0; d < 3; ++d) {
        // the translation along axis d: positions move by e_d, slopes stay. Its kinetic energy is
        // m / 2, and u_d^T M q = integral rho A r_d dx = m times the centre's coordinate d
        Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
        for (int k = d; k < n; k += 6) u[k] = 1.0;
        EXPECT_NEAR(u.dot(M * u), m, 1e-13 * m) << "axis " << d;
        EXPECT_NEAR(u.dot(M * q0), m * centre[d], 1e-13 * m) << "first moment, axis " << d;
        // on a bent beam too: the first moment is the integral of the deformed r, computed here by
        // the body's own points with Simpson's rule per element (exact for the cubic r)
        const Eigen::VectorXd q = perturbed(body, 0.1, 3);
        const double l = L / keys.elements;
        double moment = 0.0;
        for (int j = 0; j < keys.elements; ++j)
            for (int p = 0; p < 3; ++p) {
                const double x = (j + 0.5 * p) * l, weight = p == 1 ? 4.0 / 6.0 : 1.0 / 6.0;
                MaterialPoint pt;
                body.point(q, Eigen::VectorXd::Zero(n), &x, pt);
                moment += weight * l * 7.0 * pt.r[d];
            }
        EXPECT_NEAR(u.dot(M * q), moment, 1e-13 * m);
        // gravity along d: the weight m g, and the potential its force derives from
        body.gravity_forces(q, Vec3::Unit(d) * 9.81, Q);
        EXPECT_NEAR(Q.dot(u), m * 9.81, 1e-12 * m);
        EXPECT_NEAR(body.gravity_potential(q, Vec3::Unit(d) * 9.81), -9.81 * moment, 1e-12 * m);
    }
}

// ---------------------------------------------------------------- elasticity
TEST(AncfCable3d, RigidMotionsStrainNothingAndRotateTheForces) {
    Keys keys;
    auto c = make_cable(keys);
    const FlexibleBody& body = *c->body;
    const int n = body.coordinates();
    std::mt19937 rng(11);
    std::normal_distribution<double> gauss;
    const Eigen::VectorXd bent = perturbed(body, 0.05, 7);
    Eigen::VectorXd Q(n), Q_bent(n), Q_moved(n);
    body.elastic_forces(bent, Q_bent);
    for (int trial = 0; trial < 20; ++trial) {
        const Eigen::Matrix3d R =
            Eigen::Quaterniond(Eigen::Vector4d(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized())
                .toRotationMatrix();
        const Eigen::Vector3d shift(gauss(rng), gauss(rng), gauss(rng));
        const Eigen::VectorXd q = moved(body.initial_coordinates(), R, shift);
        // round-off of EA eps^2 with eps ~ 1e-16 and of EI kappa^2 with kappa ~ 1e-15
        EXPECT_LT(body.strain_energy(q), 1e-20);
        body.elastic_forces(q, Q);
        EXPECT_LT(Q.norm(), 1e-10) << "trial " << trial;
        // a bent beam moved rigidly keeps its energy, and its forces turn with it
        const Eigen::VectorXd q_bent = moved(bent, R, shift);
        EXPECT_NEAR(body.strain_energy(q_bent), body.strain_energy(bent), 1e-12 * body.strain_energy(bent));
        body.elastic_forces(q_bent, Q_moved);
        EXPECT_LT((Q_moved - moved(Q_bent, R, Eigen::Vector3d::Zero())).norm(), 1e-10 * Q_bent.norm());
    }
}

TEST(AncfCable3d, ElasticForcesAndStiffnessAreTheEnergysDerivatives) {
    for (int axial_points : {5, 2}) {
        Keys keys;
        keys.axial_points = axial_points;
        auto c = make_cable(keys);
        test::expect_elastic_derivatives(*c->body, perturbed(*c->body, 0.08, 5));
    }
}

// ---------------------------------------------------------------- cantilever
// Static equilibrium Q_e(q) + F = 0 with node 0 clamped (its position and slope held), by Newton.
Eigen::VectorXd equilibrium(const FlexibleBody& body, const Eigen::VectorXd& F) {
    const int n = body.coordinates();
    const Reduced red(n, 6);
    Eigen::VectorXd q = body.initial_coordinates(), Q(n);
    Eigen::MatrixXd dQ(n, n);
    for (int it = 0; it < 30; ++it) {
        body.elastic_forces(q, Q);
        body.elastic_jacobian(q, dQ);
        const Eigen::VectorXd dq = -red.take(dQ).lu().solve(red.take(Eigen::VectorXd(Q + F)));
        Eigen::VectorXd full = Eigen::VectorXd::Zero(n);
        red.put(dq, full);
        q += full;
        if (dq.norm() < 1e-14) return q;
    }
    ADD_FAILURE() << "Newton did not converge";
    return q;
}

TEST(AncfCable3d, SmallTipLoadInEitherTransverseDirectionGivesLinearBeamTheory) {
    // a skew beam of length 1 (EI = 1), loaded at its tip across it along two perpendicular
    // directions: deflection P L^3 / (3 EI) along the load, nothing across it; P L^2 / EI = 1e-4
    // keeps the geometric nonlinearity at 1e-8 of the deflection. The cubic Hermite element holds
    // the linear cantilever's cubic exactly, so every mesh gives it.
    Keys keys;
    keys.from = {0, 0, 0};
    const Eigen::Vector3d t = Eigen::Vector3d(2, 1, 2) / 3.0;
    keys.to = {t.x(), t.y(), t.z()};
    const Eigen::Vector3d across[2] = {Eigen::Vector3d(1, -2, 0).normalized(), t.cross(Eigen::Vector3d(1, -2, 0)).normalized()};
    const double P = 1e-4;
    for (int N : {1, 2, 4, 8}) {
        keys.elements = N;
        auto c = make_cable(keys);
        const FlexibleBody& body = *c->body;
        const int n = body.coordinates();
        for (const Eigen::Vector3d& d : across) {
            Eigen::VectorXd F = Eigen::VectorXd::Zero(n);
            F.segment<3>(n - 6) = P * d;
            const Eigen::VectorXd q = equilibrium(body, F);
            const Eigen::Vector3d deflection = q.segment<3>(n - 6) - t;
            const Eigen::Vector3d other = t.cross(d);
            std::printf("N = %d: tip deflection along the load %.10e (P L^3 / 3 EI = %.10e), across %.1e\n", N,
                        deflection.dot(d), P / 3, deflection.dot(other));
            EXPECT_NEAR(deflection.dot(d), P / 3.0, 1e-6 * P / 3.0) << "N = " << N;
            EXPECT_NEAR(deflection.dot(other), 0.0, 1e-12) << "N = " << N;
            // the tip slope turns by P L^2 / (2 EI) towards the load
            EXPECT_NEAR(q.segment<3>(n - 3).dot(d), P / 2.0, 1e-6 * P / 2.0) << "N = " << N;
        }
    }
}

// ---------------------------------------------------------------- the planar limit
TEST(AncfCable3d, InItsPlaneItIsThePlanarCable) {
    Keys keys;
    keys.from = {0.1, -0.2, 0.0};
    keys.to = {1.1, 0.5, 0.0};
    Keys flat = keys;
    flat.from.pop_back(), flat.to.pop_back();
    auto c3 = make_cable(keys);
    auto c2 = make_cable(flat, Dimension::Planar);
    const FlexibleBody &spatial = *c3->body, &planar = *c2->body;
    const int n2 = planar.coordinates(), n3 = spatial.coordinates();
    ASSERT_EQ(n3, n2 / 2 * 3);
    std::vector<int> in_plane;  // the spatial coordinates that are the planar ones
    for (int k = 0; k < n2; ++k) in_plane.push_back(k / 2 * 3 + k % 2);
    const Eigen::VectorXd q2 = [&] {
        Eigen::VectorXd q = planar.initial_coordinates();
        std::mt19937 rng(23);
        std::normal_distribution<double> gauss;
        for (int k = 0; k < n2; ++k) q[k] += 0.1 * gauss(rng);
        return q;
    }();
    Eigen::VectorXd q3 = Eigen::VectorXd::Zero(n3), v3 = Eigen::VectorXd::Zero(n3);
    const Eigen::VectorXd v2 = perturbed(planar, 1.0, 29) - planar.initial_coordinates();
    q3(in_plane) = q2;
    v3(in_plane) = v2;
    auto relative = [](const auto& a, const auto& b) { return (a - b).norm() / (1e-300 + b.norm()); };
    EXPECT_NEAR(spatial.strain_energy(q3), planar.strain_energy(q2), 1e-13 * planar.strain_energy(q2));
    Eigen::VectorXd Q2(n2), Q3(n3);
    planar.elastic_forces(q2, Q2);
    spatial.elastic_forces(q3, Q3);
    EXPECT_LT(relative(Eigen::VectorXd(Q3(in_plane)), Q2), 1e-12);
    EXPECT_NEAR(Q3.norm(), Q2.norm(), 1e-12 * Q2.norm()) << "no force out of the plane";
    Eigen::MatrixXd K2(n2, n2), K3(n3, n3), M2, M3;
    planar.elastic_jacobian(q2, K2);
    spatial.elastic_jacobian(q3, K3);
    EXPECT_LT(relative(Eigen::MatrixXd(K3(in_plane, in_plane)), K2), 1e-12);
    planar.mass_matrix(q2, M2);
    spatial.mass_matrix(q3, M3);
    EXPECT_LT(relative(Eigen::MatrixXd(M3(in_plane, in_plane)), M2), 1e-14);
    for (double x : {0.0, 0.41, 1.2}) {
        MaterialFrame f2, f3;
        planar.frame(q2, v2, &x, f2);
        spatial.frame(q3, v3, &x, f3);
        EXPECT_LT((f3.spatial.R.head<2>() - f2.planar.R).norm(), 1e-14);
        const Mat3 Rz = Eigen::AngleAxisd(f2.planar.theta, Vec3::UnitZ()).toRotationMatrix();
        EXPECT_LT((f3.spatial.A - Rz).norm(), 1e-14) << "at " << x;
        EXPECT_LT((f3.spatial.omega_bar - Vec3(0, 0, f2.planar.omega)).norm(), 1e-12 * (1 + std::abs(f2.planar.omega)));
        const Eigen::VectorXd turn3 = f3.jacobian.row(5).transpose(), turn2 = f2.jacobian.row(2).transpose();
        EXPECT_LT(relative(Eigen::VectorXd(turn3(in_plane)), turn2), 1e-13);
        EXPECT_NEAR(f3.bias[5], f2.bias[2], 1e-12 * (1 + std::abs(f2.bias[2])));
    }
}

// ---------------------------------------------------------------- the material frame
TEST(AncfCable3d, TheFramesVelocityAndAccelerationAreItsJacobianAndBias) {
    for (const std::vector<double>& normal : {std::vector<double>{}, std::vector<double>{0.3, -1, 0.2}}) {
        Keys keys;
        keys.normal = normal;
        auto c = make_cable(keys);
        const FlexibleBody& body = *c->body;
        const int n = body.coordinates();
        const Eigen::VectorXd q = perturbed(body, 0.1, 31), v = perturbed(body, 1.0, 37) - body.initial_coordinates();
        const Eigen::Vector3d nz = normal.empty() ? Eigen::Vector3d::UnitZ()
                                                  : Eigen::Vector3d(normal[0], normal[1], normal[2]).normalized();
        const double h = 1e-6;
        for (double x : {0.0, 0.52, length(keys)}) {
            MaterialFrame f, fp, fm;
            body.frame(q, v, &x, f);
            body.frame(q + h * v, v, &x, fp);
            body.frame(q - h * v, v, &x, fm);
            const Mat3& A = f.spatial.A;
            // axes: orthonormal, right-handed, x along r', z across r' in the plane of r' and n
            EXPECT_LT((A.transpose() * A - Mat3::Identity()).norm(), 1e-14);
            EXPECT_NEAR(A.determinant(), 1.0, 1e-14);
            MaterialPoint pt;
            body.point(q, v, &x, pt);
            EXPECT_LT((pt.r - f.spatial.R).norm(), 1e-15);
            EXPECT_NEAR(A.col(2).dot(A.col(0).cross(nz)), 0.0, 1e-14);
            EXPECT_GT(A.col(2).dot(nz), 0.0);
            EXPECT_LT((rotation_from_euler_parameters(f.spatial.p) - A).norm(), 1e-14);
            // velocity: Rdot and A^T Adot = [wbar]
            const Eigen::VectorXd Gv = f.jacobian * v;
            const Mat3 spin = A.transpose() * (fp.spatial.A - fm.spatial.A) / (2 * h);
            const Vec3 wbar(spin(2, 1), spin(0, 2), spin(1, 0));
            EXPECT_LT((Gv.head<3>() - (fp.spatial.R - fm.spatial.R) / (2 * h)).norm(), 1e-8 * (1 + Gv.norm()));
            EXPECT_LT((Gv.tail<3>() - wbar).norm(), 1e-7 * (1 + wbar.norm())) << "at " << x;
            EXPECT_LT((f.spatial.Rdot - Gv.head<3>()).norm(), 1e-14 * (1 + Gv.norm()));
            EXPECT_LT((f.spatial.omega_bar - Gv.tail<3>()).norm(), 1e-14 * (1 + Gv.norm()));
            EXPECT_LT((pt.rdot - pt.jacobian * v).norm(), 1e-14 * (1 + Gv.norm()));
            // acceleration at vdot = 0: the rates of Rdot and wbar along q + t v are the bias
            Eigen::VectorXd rate(6);
            rate << (fp.spatial.Rdot - fm.spatial.Rdot) / (2 * h), (fp.spatial.omega_bar - fm.spatial.omega_bar) / (2 * h);
            EXPECT_LT((rate - f.bias).norm(), 1e-6 * (1 + rate.norm())) << "bias at " << x;
            std::printf("frame at %.2f: |wbar| %.3f, G v error %.1e, |bias| %.3f, bias error %.1e\n", x, wbar.norm(),
                        (Gv.tail<3>() - wbar).norm(), f.bias.norm(), (rate - f.bias).norm());
        }
        (void)n;
    }
}

// ---------------------------------------------------------------- bad input
std::string refusal(const Keys& keys) {
    try {
        make_cable(keys);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(AncfCable3d, BadInputIsRefusedNamingTheBody) {
    const auto expect_refused = [](const Keys& k, const std::string& what) {
        const std::string message = refusal(k);
        EXPECT_NE(message.find("body 'beam'"), std::string::npos) << message;
        EXPECT_NE(message.find("beam.yaml:3"), std::string::npos) << message;
        EXPECT_NE(message.find(what), std::string::npos) << message;
    };
    Keys k;
    k.modulus = 0;
    expect_refused(k, "'modulus' must be positive");
    k = {}, k.modulus = -2e11;
    expect_refused(k, "'modulus' must be positive");
    k = {}, k.area = -1;
    expect_refused(k, "'area' must be positive");
    k = {}, k.area = 0;
    expect_refused(k, "'area' must be positive");
    k = {}, k.second_moment = 0;
    expect_refused(k, "'second_moment' must be positive");
    k = {}, k.density = -1;
    expect_refused(k, "'density' must be positive");
    k = {}, k.to = k.from;
    expect_refused(k, "zero length");
    k = {}, k.elements = 0;
    expect_refused(k, "needs two nodes");
    k = {}, k.normal = {0, 0, 0};
    expect_refused(k, "'normal' must be a non-zero direction");
    k = {}, k.normal = {2, 1.4, 1.2};  // along to - from
    expect_refused(k, "'normal' is along the beam");
    k = {}, k.to = {1, 2};  // a planar point in a spatial scene
    EXPECT_NE(refusal(k), "(accepted)");
    // a material point beyond the end of the beam
    auto c = make_cable(Keys{});
    const double inside = length(Keys{}), beyond = 1.001 * inside;
    EXPECT_NO_THROW(c->body->check_material_point(&inside));
    EXPECT_THROW(c->body->check_material_point(&beyond), InputError);
}

// ---------------------------------------------------------------- in a spatial scene
// rho A = 1 kg/m, EI = 10 N m^2, EA = 1e4 N, as the planar scene tests (test_flexible_scene.cpp).
std::string spatial_cable(const std::string& to, int elements, const std::string& extra = "") {
    return "dimension: spatial\ngravity: [0, 0, -9.81]\nflexible_bodies:\n"
           "  - {name: rope, type: ancf_cable, from: [0, 0, 0], to: " + to + ", elements: " + std::to_string(elements) +
           ", modulus: 1.0e4, area: 1.0, second_moment: 1.0e-3, density: 1.0" + extra + "}\n";
}

using Trace = test::SampledRun;

Trace run(const std::string& scene_text, double t_end, double tolerance) {
    return test::run_sampled(test::scene(scene_text), test::adaptive_run("augmented", "dopri5", tolerance, t_end, t_end / 30));
}

TEST(AncfCable3dScene, AFreeCableFallsAsAPointUnderGravity) {
    // along y with 4 elements, so that every node and slope is exact in binary (a skew beam's
    // round-off strain of 1e-16 shakes its stiff slope coordinates at 1e-9 m/s)
    const Trace trace = run(spatial_cable("[0, 1, 0]", 4), 0.5, 1e-10);
    ASSERT_EQ(trace.rows.size(), 31u);
    double worst = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) {
        const double t = trace.at(r, "t");
        for (int k = 0; k <= 4; ++k) {
            const std::string node = "rope.node" + std::to_string(k);
            worst = std::max({worst, std::abs(trace.at(r, node + ".x")), std::abs(trace.at(r, node + ".y") - 0.25 * k),
                              std::abs(trace.at(r, node + ".z") + 0.5 * 9.81 * t * t),
                              std::abs(trace.at(r, node + ".vz") + 9.81 * t)});
        }
    }
    std::printf("spatial free fall: largest node error %.3g m, energy change %.3g J\n", worst, trace.largest_energy_change());
    // exact but for round-off: RK of order >= 2 integrates a constant acceleration exactly, and a
    // uniform field strains nothing
    EXPECT_LT(worst, 1e-10);
    EXPECT_LT(trace.largest_energy_change(), 1e-10);
}

TEST(AncfCable3dScene, AFlexiblePendulumOnATiltedHingeKeepsItsEnergyAndItsHinge) {
    // hinged at node 0 about a = (0, 0.6, 0.8), released along x under gravity -z: it swings
    // about a and, gravity having a part 0.8 g along a, bends out of the swing's plane (a
    // cantilever's static sag under that part is w L^4 / (8 EI) = 0.098 m). The frame's reference
    // direction `normal` is a, so the revolute's rows (J_f G) hold node 0's tangent across a.
    const std::string hinge =
        "joints:\n  - {name: hinge, type: revolute, bodies: [ground, {body: rope, node: 0}], point: [0, 0, 0], "
        "axis: [0, 0.6, 0.8]}\n";
    const Model model = test::scene(spatial_cable("[1, 0, 0]", 3, ", normal: [0, 0.6, 0.8]") + hinge);
    const double t_end = 1.0, tolerance = 1e-9;  // past the bottom of the first swing
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", tolerance, t_end, t_end / 30);
    settings.diagnostics = true;
    Trace trace;
    const FlexibleBodyInstance& rope = model.flexible_bodies.at(0);
    const Eigen::Vector3d axis(0, 0.6, 0.8);
    double across = 0.0;  // node 0's tangent along the hinge's axis
    const SimulationResult result = simulate(model, test::shared_registry(), settings, [&](const SimulationSample& s) {
        trace.rows.push_back(*s.row);
        const Eigen::VectorXd q = s.state.q.segment(rope.offset, rope.size);
        across = std::max(across, std::abs(q.segment<3>(3).normalized().dot(axis)));
        return true;
    });
    trace.columns = result.columns;
    double pin = 0.0, lowest = 0.0, violation = 0.0, off_plane = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) {
        for (const char* c : {"rope.node0.x", "rope.node0.y", "rope.node0.z"}) pin = std::max(pin, std::abs(trace.at(r, c)));
        off_plane = std::max(off_plane, std::abs(0.6 * trace.at(r, "rope.node3.y") + 0.8 * trace.at(r, "rope.node3.z")));
        lowest = std::min(lowest, trace.at(r, "rope.node3.z"));
        violation = std::max(violation, std::abs(trace.at(r, "constraint_position_violation")));
    }
    const double scale = 1.0 * 9.81 * 0.5;  // m g L / 2
    std::printf("tilted flexible pendulum over %g s: energy drift %.3g J of %.3g, |C| %.3g, pin %.3g m, tangent . axis "
                "%.3g, tip off the swing plane %.3f m, tip lowest z %.3f\n",
                t_end, trace.largest_energy_change(), scale, violation, pin, across, off_plane, lowest);
    EXPECT_LT(trace.largest_energy_change(), 10 * tolerance * scale);  // the bound of test_flexible_scene's pendulum
    EXPECT_LT(violation, 1e-12);
    EXPECT_LT(pin, 1e-12);
    EXPECT_LT(across, 1e-12);
    EXPECT_LT(lowest, -0.45) << "the tip swings down";
}

TEST(AncfCable3dScene, AClampedCantileverKeepsItsClampAndItsEnergy) {
    // a `fixed` joint at node 0: 6 rows on the material frame, of which the cable's coordinates
    // see 5 (position and tangent; the twist is the frame's convention, not a coordinate), so one
    // row is redundant; the augmented formulation takes it. Released straight under gravity, the
    // cantilever swings about its static sag w L^4 / (8 EI) = 0.12 m.
    const std::string clamp =
        "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: rope, node: 0}], point: [0, 0, 0]}\n";
    const Model model = test::scene(spatial_cable("[1, 0, 0]", 4) + clamp);
    const double t_end = 0.4, tolerance = 1e-9;
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", tolerance, t_end, t_end / 20);
    settings.diagnostics = true;
    Trace trace;
    const FlexibleBodyInstance& rope = model.flexible_bodies.at(0);
    double held = 0.0;  // node 0's position and tangent against their clamped values (its slope may stretch)
    const SimulationResult result = simulate(model, test::shared_registry(), settings, [&](const SimulationSample& s) {
        trace.rows.push_back(*s.row);
        const Eigen::VectorXd node0 = s.state.q.segment(rope.offset, 6);
        held = std::max({held, node0.head<3>().norm(), (node0.tail<3>().normalized() - Eigen::Vector3d::UnitX()).norm()});
        return true;
    });
    trace.columns = result.columns;
    double lowest = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) lowest = std::min(lowest, trace.at(r, "rope.node4.z"));
    const double scale = 1.0 * 9.81 * 0.12;  // the weight times the sag: the energy the swing exchanges
    std::printf("clamped cantilever over %g s: energy drift %.3g J of %.3g, node 0 off its clamp %.3g, tip lowest "
                "z %.3f\n",
                t_end, trace.largest_energy_change(), scale, held, lowest);
    EXPECT_LT(trace.largest_energy_change(), 10 * tolerance * scale);
    EXPECT_LT(held, 1e-12);
    EXPECT_LT(lowest, -0.15) << "the tip swings below its static sag";
    EXPECT_GT(lowest, -0.35) << "and not far past twice it";
}

TEST(AncfCable3dScene, ARigidBallHungFromThePinnedCableKeepsTheEnergyAndTheJoints) {
    // A rigid body before the cable in the coordinates: 7 of q but 6 of v, so the cable's first
    // coordinate (7) and first velocity (6) differ; every place that takes one for the other
    // (the mass block, the forces, the Jacobian's columns, the CSV's velocities) breaks this.
    // The cable is pinned at node 0 and carries a 0.5 kg ball at its tip, released horizontal.
    const std::string scene = spatial_cable("[1, 0, 0]", 3) +
                              "bodies:\n  - {name: ball, mass: 0.5, inertia: [1.0e-3, 1.0e-3, 1.0e-3], position: [1, 0, 0]}\n"
                              "joints:\n"
                              "  - {name: pin, type: spherical, bodies: [ground, {body: rope, node: 0}], point: [0, 0, 0]}\n"
                              "  - {name: tip, type: spherical, bodies: [{body: rope, node: 3}, ball], point: [1, 0, 0]}\n";
    const Model model = test::scene(scene);
    ASSERT_EQ(model.flexible_bodies.at(0).offset, 7);
    ASSERT_EQ(model.flexible_bodies.at(0).v_offset, 6);
    const double t_end = 0.5, tolerance = 1e-9;
    const Trace trace = run(scene, t_end, tolerance);
    double apart = 0.0, pin = 0.0, lowest = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) {
        for (const char* c : {"x", "y", "z"}) {
            apart = std::max(apart, std::abs(trace.at(r, std::string("rope.node3.") + c) - trace.at(r, std::string("ball.") + c)));
            pin = std::max(pin, std::abs(trace.at(r, std::string("rope.node0.") + c)));
        }
        lowest = std::min(lowest, trace.at(r, "ball.z"));
    }
    const double scale = (1.0 * 0.5 + 0.5 * 1.0) * 9.81;  // the cable's and the ball's m g h from the top
    std::printf("ball on a pinned spatial cable over %g s: energy drift %.3g J of %.3g, tip to ball %.3g m, pin %.3g m, "
                "ball lowest z %.3f\n", t_end, trace.largest_energy_change(), scale, apart, pin, lowest);
    EXPECT_LT(trace.largest_energy_change(), 10 * tolerance * scale);
    EXPECT_LT(apart, 1e-9);
    EXPECT_LT(pin, 1e-9);
    EXPECT_LT(lowest, -0.5) << "the ball swings down";
}

// The frame at a joint's node is undefined where the tangent lies along `normal` (default z for a
// beam along x): the run stops with an error naming the body, its line and the time, not the
// plugin's bare DomainError.
TEST(AncfCable3dScene, ATangentAlongTheNormalStopsTheRunNamingTheBodyAndTheTime) {
    const Model model = test::scene(spatial_cable("[1, 0, 0]", 2) +
                                        "joints:\n  - {name: pin, type: spherical, bodies: [ground, {body: rope, node: 0}], "
                                        "point: [0, 0, 0]}\n",
                                    "cable.yaml");
    ModelSystem system(model);
    State state = system.initial_state();
    state.t = 0.25;
    const int o = model.flexible_bodies.front().offset;
    state.q.segment<3>(o + 3) = Eigen::Vector3d(0, 0, 1);  // node 0's slope r' turned onto z
    ConstraintValues cv;
    try {
        system.constraints(state, cv, true);
        ADD_FAILURE() << "no error";
    } catch (const DynamicsError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("flexible body 'rope'"), std::string::npos) << m;
        EXPECT_NE(m.find("cable.yaml:4"), std::string::npos) << m;
        EXPECT_NE(m.find("t = 0.25"), std::string::npos) << m;
        EXPECT_NE(m.find("parallel to its reference direction 'normal'"), std::string::npos) << m;
        EXPECT_EQ(e.time(), 0.25);
    }
}

}  // namespace
}  // namespace mbd
