// The planar shear-deformable ANCF beam (`ancf_beam`, plugins/bodies/ancf ancf_beam*) against
// independent oracles: Timoshenko's cantilever P L^3 / (3 EI) + P L / (k G A) for a thick beam,
// Euler-Bernoulli's P L^3 / (3 EI) for a thin one (no shear locking), the mass, first moment and
// rotary inertia of the beam, rigid motions that strain nothing, finite differences of its own
// energy, forces and frame, and refusals of bad input naming the body.
#include "support/flexible_body.hpp"

#include <mbd/sdk/body.hpp>
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

// A square section of side h from (0, 0) to (L, 0); E = 1e7, G = E / 2.6 (Poisson 0.3), rho 100.
struct Keys {
    double length = 1.0, side = 0.4;
    int elements = 4;
    double modulus = 1e7, shear_modulus = 1e7 / 2.6, density = 100.0;
    double area() const { return side * side; }
    double second_moment() const { return side * side * side * side / 12.0; }
    double shear_factor = 5.0 / 6.0;
    bool give_shear_factor = false;
};

std::map<std::string, Param> fields(const Keys& k) {
    std::map<std::string, Param> f = {{"from", test::list_param({0, 0})},
                                      {"to", test::list_param({k.length, 0})},
                                      {"elements", number_param(k.elements)},
                                      {"modulus", number_param(k.modulus)},
                                      {"shear_modulus", number_param(k.shear_modulus)},
                                      {"area", number_param(k.area())},
                                      {"second_moment", number_param(k.second_moment())},
                                      {"density", number_param(k.density)}};
    if (k.give_shear_factor) f["shear_factor"] = number_param(k.shear_factor);
    return f;
}

std::unique_ptr<test::BodyFromKeys> make_beam(const Keys& k) { return test::make_body("ancf_beam", fields(k)); }

// The coordinates a cantilever clamp leaves free: node 0's position and director held (its
// section), its centre line's slope free (it differs from the section by the shear angle).
std::vector<int> cantilever_free(int n) {
    std::vector<int> free = {2, 3};
    for (int k = 6; k < n; ++k) free.push_back(k);
    return free;
}

// Tip deflection (along y) under a tip load -P along y, by Newton on the free coordinates.
double tip_deflection(const FlexibleBody& body, double P) {
    const int n = body.coordinates();
    const std::vector<int> free = cantilever_free(n);
    Eigen::VectorXd q = body.initial_coordinates(), Q(n), F = Eigen::VectorXd::Zero(n);
    F[n - 5] = -P;  // the last node's y
    Eigen::MatrixXd dQ(n, n);
    for (int it = 0; it < 30; ++it) {
        body.elastic_forces(q, Q);
        body.elastic_jacobian(q, dQ);
        const Eigen::VectorXd residual = Q + F;
        const Eigen::VectorXd dq = -Eigen::MatrixXd(dQ(free, free)).lu().solve(Eigen::VectorXd(residual(free)));
        q(free) += dq;
        if (dq.norm() < 1e-12) return -q[n - 5];  // linear: the second step is round-off (1e-8 of the tip here)
    }
    ADD_FAILURE() << "Newton did not converge";
    return -q[n - 5];
}

TEST(AncfBeam, ThickCantileverConvergesToTimoshenko) {
    Keys keys;  // L / h = 2.5: shear adds 12.5% to the bending deflection
    const double EI = keys.modulus * keys.second_moment(), kGA = 5.0 / 6.0 * keys.shear_modulus * keys.area();
    const double P = 1e-4 * EI;  // P L^2 / EI = 1e-4: linear
    const double exact = P / (3 * EI) + P / kGA, bending = P / (3 * EI);
    double previous = 0.0, error = 0.0;
    for (int N : {2, 4, 8, 16, 32}) {
        keys.elements = N;
        auto b = make_beam(keys);
        const double w = tip_deflection(*b->body, P);
        error = std::abs(w - exact) / exact;
        std::printf("N = %2d: tip %.10e, Timoshenko %.10e, relative error %.3e%s", N, w, exact, error,
                    previous > 0 ? "" : "\n");
        if (previous > 0) {
            const double rate = std::log2(previous / error);
            std::printf(", rate %.2f\n", rate);
            EXPECT_GT(rate, 1.8) << "N = " << N;  // the linear director: error O(h^2)
            EXPECT_LT(rate, 2.2) << "N = " << N;
        }
        previous = error;
    }
    EXPECT_LT(error, 3e-4);
    EXPECT_GT(std::abs(exact - bending) / exact, 300 * error) << "the oracle tells shear from no shear";
}

TEST(AncfBeam, AThinCantileverDoesNotLock) {
    // L / h = 1000: an element whose shear constraint over-stiffens bending (shear locking) gives a
    // deflection of order (h / L)^2 of the true one. The linear director's own error for a tip
    // load is about 1 / (4 N^2) (1/4 with 1 element, 1.6% with 4, 0.7% with 6).
    Keys keys;
    keys.side = 1e-3;
    const double EI = keys.modulus * keys.second_moment(), kGA = 5.0 / 6.0 * keys.shear_modulus * keys.area();
    const double P = 1e-4 * EI, euler_bernoulli = P / (3 * EI);
    for (int N : {1, 2, 6}) {
        keys.elements = N;
        auto b = make_beam(keys);
        const double w = tip_deflection(*b->body, P);
        const double expected = euler_bernoulli * (1 - 1.0 / (4 * N * N)) + P / kGA;
        std::printf("thin, N = %d: tip / (P L^3 / 3 EI) = %.8f (1 - 1/(4N^2) = %.8f)\n", N, w / euler_bernoulli,
                    1 - 1.0 / (4 * N * N));
        EXPECT_NEAR(w, expected, 1e-3 * euler_bernoulli) << "N = " << N;
        if (N == 6) EXPECT_NEAR(w, euler_bernoulli, 0.01 * euler_bernoulli);
    }
}

TEST(AncfBeam, MassMatrixGivesTheMassFirstMomentAndRotaryInertia) {
    Keys keys;
    keys.length = 2.0, keys.elements = 3;
    auto b = make_beam(keys);
    const FlexibleBody& body = *b->body;
    const int n = body.coordinates();
    const double rhoA = keys.density * keys.area(), rhoI = keys.density * keys.second_moment(), m = rhoA * 2.0;
    const Eigen::VectorXd q0 = body.initial_coordinates();
    Eigen::MatrixXd M;
    body.mass_matrix(q0, M);
    for (int d = 0; d < 2; ++d) {  // a translation: positions move, gradients stay
        Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
        for (int k = d; k < n; k += 6) u[k] = 1.0;
        EXPECT_NEAR(u.dot(M * u), m, 1e-13 * m);
        EXPECT_NEAR(u.dot(M * q0), d == 0 ? m * 1.0 : 0.0, 1e-13 * m) << "the first moment: centre at (1, 0)";
        Eigen::VectorXd Q(n);
        body.gravity_forces(q0, Vec3::Unit(d) * 9.81, Q);
        EXPECT_NEAR(Q.dot(u), m * 9.81, 1e-12 * m);
    }
    // a unit spin about the centre (1, 0): every material vector turns, v = k x (r - c) for the
    // positions and k x r_x, k x r_y for the gradients; kinetic energy (rho A L^3 / 12 + rho I L) / 2
    Eigen::VectorXd spin(n);
    for (int k = 0; k < n; k += 6) {
        const Eigen::Vector2d r = q0.segment<2>(k) - Eigen::Vector2d(1, 0);
        spin.segment<2>(k) << -r.y(), r.x();
        for (int g : {2, 4}) spin.segment<2>(k + g) << -q0[k + g + 1], q0[k + g];
    }
    const double J = rhoA * 8.0 / 12.0 + rhoI * 2.0;
    EXPECT_NEAR(spin.dot(M * spin), J, 1e-13 * J);
}

TEST(AncfBeam, RigidMotionsStrainNothing) {
    auto b = make_beam(Keys{});
    const FlexibleBody& body = *b->body;
    const int n = body.coordinates();
    Eigen::VectorXd Q(n);
    for (double angle : {0.3, 2.0, -2.9}) {
        const Eigen::Matrix2d R = Eigen::Rotation2Dd(angle).toRotationMatrix();
        Eigen::VectorXd q = body.initial_coordinates();
        for (int k = 0; k < n; k += 6) {
            q.segment<2>(k) = R * q.segment<2>(k) + Eigen::Vector2d(0.3, -1.2);
            q.segment<2>(k + 2) = R * q.segment<2>(k + 2);
            q.segment<2>(k + 4) = R * q.segment<2>(k + 4);
        }
        EXPECT_LT(body.strain_energy(q), 1e-20) << "angle " << angle;
        body.elastic_forces(q, Q);
        // round-off: EA = 1.6e6 times strains of 1e-16, summed over the Gauss points and elements
        const Keys k;
        EXPECT_LT(Q.norm(), 1e-14 * k.modulus * k.area()) << "angle " << angle;
        // the cross-section's frame turns with it
        const double x = 0.7;
        MaterialFrame f;
        body.frame(q, Eigen::VectorXd::Zero(n), &x, f);
        EXPECT_NEAR(std::remainder(f.planar.theta - angle, 2 * M_PI), 0.0, 1e-14);
    }
}

TEST(AncfBeam, ElasticForcesStiffnessAndFrameAgreeWithFiniteDifferences) {
    auto b = make_beam(Keys{});
    const FlexibleBody& body = *b->body;
    const int n = body.coordinates();
    std::mt19937 rng(41);
    std::normal_distribution<double> gauss;
    Eigen::VectorXd q = body.initial_coordinates(), v(n);
    for (int k = 0; k < n; ++k) q[k] += 0.05 * gauss(rng), v[k] = gauss(rng);
    test::expect_elastic_derivatives(body, q);
    for (double x : {0.0, 0.3, 1.0}) test::expect_frame_derivatives(body, q, v, x, 1e-6);
}

std::string refusal(const Keys& keys, const std::string& drop = "", Dimension dimension = Dimension::Planar) {
    try {
        auto b = std::make_unique<test::BodyFromKeys>();
        b->node = test::scalar_param("");
        b->node.kind = Param::Kind::Map;
        b->node.fields = fields(keys);
        b->node.fields.erase(drop);
        b->spec = {"beam", "ancf_beam", dimension, Params("body 'beam'", &b->node)};
        test::shared_registry().create_body(b->spec, "beam.yaml:2");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(AncfBeam, BadInputIsRefusedNamingTheBody) {
    const auto expect_refused = [](const std::string& message, const std::string& what) {
        EXPECT_NE(message.find("body 'beam'"), std::string::npos) << message;
        EXPECT_NE(message.find(what), std::string::npos) << message;
    };
    Keys k;
    k.modulus = 0;
    expect_refused(refusal(k), "'modulus' must be positive");
    k = {}, k.shear_modulus = -1;
    expect_refused(refusal(k), "'shear_modulus' must be positive");
    k = {}, k.side = 0;
    expect_refused(refusal(k), "'area' must be positive");
    k = {}, k.density = 0;
    expect_refused(refusal(k), "'density' must be positive");
    k = {}, k.give_shear_factor = true, k.shear_factor = 0;
    expect_refused(refusal(k), "'shear_factor' must be positive");
    k = {}, k.length = 0;
    expect_refused(refusal(k), "zero length");
    k = {}, k.elements = 0;
    expect_refused(refusal(k), "needs two nodes");
    EXPECT_NE(refusal(k).find("beam.yaml:3"), std::string::npos) << refusal(k);
    expect_refused(refusal(Keys{}, "shear_modulus"), "shear_modulus");
    expect_refused(refusal(Keys{}, "", Dimension::Spatial), "planar");
}

TEST(AncfBeam, APinnedBeamInASceneSwingsKeepingItsEnergy) {
    // a 10 cm square beam (rho A = 1 kg/m, EI = 8.3 N m^2) pinned at node 0, released horizontal;
    // a soft modulus keeps its fastest mode (the section's stretch, sqrt(EA / rho I) = 3.5e3 rad/s)
    // cheap for the explicit integrator
    const std::string text =
        "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n"
        "  - {name: bar, type: ancf_beam, from: [0, 0], to: [1, 0], elements: 2, modulus: 1.0e6, "
        "shear_modulus: 3.846e5, area: 0.01, second_moment: 8.333333e-6, density: 100}\n"
        "joints:\n  - {name: pin, type: revolute, bodies: [ground, {body: bar, node: 0}]}\n";
    const Model model = test::scene(text);
    const double t_end = 0.6, tolerance = 1e-9;
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", tolerance, t_end, t_end / 20);
    settings.diagnostics = true;
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
    const SimulationResult result = simulate(model, test::shared_registry(), settings, [&](const SimulationSample& s) {
        rows.push_back(*s.row);
        return true;
    });
    columns = result.columns;
    const auto column = [&](const std::string& name) {
        return static_cast<size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
    };
    ASSERT_LT(column("bar.node2.y"), columns.size());
    const auto energy = [&](size_t r) { return rows[r][column("kinetic_energy")] + rows[r][column("potential_energy")]; };
    double drift = 0.0, pin = 0.0, lowest = 0.0;
    for (size_t r = 0; r < rows.size(); ++r) {
        drift = std::max(drift, std::abs(energy(r) - energy(0)));
        pin = std::max({pin, std::abs(rows[r][column("bar.node0.x")]), std::abs(rows[r][column("bar.node0.y")])});
        lowest = std::min(lowest, rows[r][column("bar.node2.y")]);
    }
    const double scale = 1.0 * 9.81 * 0.5;  // m g L / 2
    std::printf("pinned ancf_beam over %g s: energy drift %.3g J of %.3g, pin %.3g m, tip lowest %.3f\n", t_end, drift,
                scale, pin, lowest);
    EXPECT_LT(drift, 10 * tolerance * scale);  // the bound of test_flexible_scene's pendulum
    EXPECT_LT(pin, 1e-12);
    EXPECT_LT(lowest, -0.8) << "it swings through the bottom";
}

}  // namespace
}  // namespace mbd
