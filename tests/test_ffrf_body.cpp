// The planar FFRF body plugin `ffrf_body` (plugins/bodies/ffrf, sdk body.hpp) against independent
// oracles: Euler-Bernoulli cantilever frequencies from its beam modes, the mass matrix against the
// kinetic energy of its own material points, the quadratic-velocity forces against Lagrange's
// equations by finite differences of the mass matrix, frames by finite differences, energy and
// momentum of a free-floating body under the test's own RK4, the rotating beam with and without
// geometric stiffening, and refusals of bad input naming the body.
#include "support/flexible_body.hpp"
#include "support/input_files.hpp"

#include <boost/math/quadrature/gauss.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <sstream>

namespace mbd {
namespace {

using test::list_param;
using test::number_param;
using test::scalar_param;

struct BeamKeys {
    double length = 1.0;
    int elements = 8, modes = 4;
    double modulus = 1e6, area = 1.0, second_moment = 1e-6, density = 1.0;  // EI = 1, rho A = 1
    bool stiffening = false;
};

std::unique_ptr<test::BodyFromKeys> make_beam(const BeamKeys& k) {
    std::map<std::string, Param> fields = {{"from", list_param({0, 0})},
                                           {"to", list_param({k.length, 0})},
                                           {"elements", number_param(k.elements)},
                                           {"modes", number_param(k.modes)},
                                           {"modulus", number_param(k.modulus)},
                                           {"area", number_param(k.area)},
                                           {"second_moment", number_param(k.second_moment)},
                                           {"density", number_param(k.density)}};
    if (k.stiffening) fields["geometric_stiffening"] = scalar_param("true");
    return test::make_body("ffrf_body", fields);
}

// ---------------------------------------------------------------- a general mode file
// Three lumped masses off the frame's axis and two modes moving them in x, y and turning them, so
// that every inertia integral (I0f, Stilde too, which a transverse beam mode leaves zero) is
// exercised. Mode 2 is made mass-orthogonal to mode 1 and the modal masses are the lumped sums,
// so the body's M must equal sum m_k L_k^T L_k exactly.
struct LumpedModes {
    std::vector<Eigen::Vector2d> u0 = {{0.0, 0.0}, {1.0, 0.2}, {2.0, -0.1}};
    std::vector<double> mass = {1.0, 2.0, 0.5};
    std::vector<Eigen::Matrix<double, 3, 2>> modes;  // per node: (ux, uy, rotation) x mode
    double stiffness[2] = {30.0, 200.0};
    double modal_mass(int i) const {
        double s = 0;
        for (size_t k = 0; k < mass.size(); ++k) s += mass[k] * modes[k].col(i).head<2>().squaredNorm();
        return s;
    }
    LumpedModes() {
        modes.resize(3);
        modes[0] << 0.0, 0.0, 0.0, 0.0, 0.0, 0.0;
        modes[1] << 0.05, 0.3, 0.4, -0.2, 0.3, 0.1;
        modes[2] << -0.1, 0.6, 1.0, 0.5, 0.7, -0.4;
        double dot = 0;  // Gram-Schmidt in the lumped mass
        for (size_t k = 0; k < 3; ++k) dot += mass[k] * modes[k].col(0).head<2>().dot(modes[k].col(1).head<2>());
        const double ratio = dot / modal_mass(0);
        for (auto& m : modes) m.col(1) -= ratio * m.col(0);
    }
    std::string text() const {
        std::ostringstream out;
        out.precision(17);
        out << "# three lumped masses\nnodes 3\n";
        for (size_t k = 0; k < 3; ++k) out << u0[k].x() << " " << u0[k].y() << " " << mass[k] << "\n";
        for (int i = 0; i < 2; ++i) {
            out << "mode " << modal_mass(i) << " " << stiffness[i] << "  # modal mass, stiffness\n";
            for (size_t k = 0; k < 3; ++k) out << modes[k](0, i) << " " << modes[k](1, i) << " " << modes[k](2, i) << "\n";
        }
        return out.str();
    }
};

// A body from a mode file of `text` (none written when empty), given relative to the scene
// file's folder.
std::unique_ptr<test::BodyFromKeys> make_from_file(const std::string& text, const std::string& name = "modes.txt") {
    const auto dir = test::scratch("ffrf_body");
    if (!text.empty()) test::write_text(dir / name, text);
    Param file = scalar_param(name);
    file.file = (dir / "beam.yaml").string();
    return test::make_body("ffrf_body", {{"mode_file", file}, {"position", list_param({0.4, -0.3})},
                                         {"angle", number_param(0.6)}});
}

// A random state near the body's initial configuration.
void random_state(const FlexibleBody& body, int seed, double spread, Eigen::VectorXd& q, Eigen::VectorXd& v) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss;
    q = body.initial_coordinates();
    v.resize(q.size());
    for (int k = 0; k < q.size(); ++k) q[k] += spread * gauss(rng), v[k] = gauss(rng);
}

Eigen::MatrixXd mass_at(const FlexibleBody& body, const Eigen::VectorXd& q) {
    Eigen::MatrixXd M;
    body.mass_matrix(q, M);
    return M;
}

// ---------------------------------------------------------------- frequencies
TEST(FfrfBody, CantileverModesGiveEulerBernoulliFrequencies) {
    // omega_i = (beta_i L)^2 sqrt(EI / (rho A L^4)) with EI = rho A = L = 1, the frame held
    const double beta[4] = {1.875104068711961, 4.694091132974175, 7.854757438237613, 10.99554073487547};
    BeamKeys keys;
    keys.elements = 100;
    auto b = make_beam(keys);
    const FlexibleBody& body = *b->body;
    const int n = body.coordinates();
    ASSERT_EQ(n, 7);
    const Eigen::VectorXd q = body.initial_coordinates();
    Eigen::MatrixXd dQ(n, n);
    body.elastic_jacobian(q, dQ);
    const test::Reduced modes(n, 3);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(-modes.take(dQ), modes.take(mass_at(body, q)));
    for (int i = 0; i < 4; ++i) {
        const double exact = beta[i] * beta[i], omega = std::sqrt(eig.eigenvalues()[i]);
        std::printf("mode %d: omega %.12f, beta L %.12f, relative error %.2e\n", i + 1, omega, std::sqrt(omega),
                    std::abs(omega - exact) / exact);
        EXPECT_NEAR(omega, exact, 1e-6 * exact) << "mode " << i + 1;
    }
    // the rigid inertia of a uniform bar along x from the frame's origin: m = rho A L,
    // first moment (0, m L / 2) turned by P, m L^2 / 3 about the origin
    const Eigen::MatrixXd M = mass_at(body, q);
    EXPECT_NEAR(M(0, 0), 1.0, 1e-12);
    EXPECT_NEAR(M(1, 2), 0.5, 1e-12);
    EXPECT_NEAR(M(0, 2), 0.0, 1e-12);
    EXPECT_NEAR(M(2, 2), 1.0 / 3.0, 1e-12);
}

// ---------------------------------------------------------------- mass matrix
// M = int rho L^T L over the material points, L = the point's Jacobian: the beam by Gauss
// quadrature of the test's own (boost, 10 points per element), the lumped file by the sum.
TEST(FfrfBody, MassMatrixIsTheKineticEnergyOfItsMaterialPoints) {
    BeamKeys keys;
    keys.length = 2.0, keys.elements = 5, keys.density = 3.0;  // rho A = 3
    auto b = make_beam(keys);
    Eigen::VectorXd q, v;
    random_state(*b->body, 3, 0.2, q, v);
    const int n = b->body->coordinates();
    Eigen::MatrixXd integral = Eigen::MatrixXd::Zero(n, n);
    const double l = keys.length / keys.elements;
    for (int j = 0; j < keys.elements; ++j) {
        auto density = [&](double x, int r, int c) {
            MaterialPoint pt;
            b->body->point(q, v, &x, pt);
            return 3.0 * pt.jacobian.col(r).dot(pt.jacobian.col(c));
        };
        for (int r = 0; r < n; ++r)
            for (int c = 0; c < n; ++c)
                integral(r, c) += boost::math::quadrature::gauss<double, 10>::integrate(
                    [&](double x) { return density(x, r, c); }, j * l, (j + 1) * l);
    }
    EXPECT_LT((mass_at(*b->body, q) - integral).norm(), 1e-11 * integral.norm());

    const LumpedModes lumped;
    auto f = make_from_file(lumped.text());
    random_state(*f->body, 4, 0.2, q, v);
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(5, 5);
    for (int k = 0; k < 3; ++k) {
        MaterialPoint pt;
        const double node = k;
        f->body->point(q, v, &node, pt);
        sum += lumped.mass[k] * pt.jacobian.transpose() * pt.jacobian;
        // the node's position from the file's data, by hand
        const Eigen::Vector2d u = lumped.u0[k] + lumped.modes[k].topRows<2>() * q.tail<2>();
        EXPECT_LT((pt.r.head<2>() - (q.head<2>() + Eigen::Rotation2Dd(q[2]) * u)).norm(), 1e-14);
    }
    EXPECT_LT((mass_at(*f->body, q) - sum).norm(), 1e-12 * sum.norm());
}

// Lagrange's equations for T = v^T M(q) v / 2 with v = qdot: Q_v = -Mdot v + dT/dq, both from
// central differences of the body's own M.
void expect_lagrange_quadratic_velocity(const FlexibleBody& body, int seed) {
    Eigen::VectorXd q, v;
    random_state(body, seed, 0.3, q, v);
    const int n = body.coordinates();
    const double h = 1e-6;
    const Eigen::VectorXd Mdot_v = (mass_at(body, q + h * v) - mass_at(body, q - h * v)) * v / (2 * h);
    Eigen::VectorXd dT(n);
    for (int k = 0; k < n; ++k) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
        e[k] = h;
        dT[k] = 0.5 * v.dot((mass_at(body, q + e) - mass_at(body, q - e)) * v) / (2 * h);
    }
    const Eigen::VectorXd expected = -Mdot_v + dT;
    Eigen::VectorXd Qv(n);
    body.quadratic_velocity_forces(q, v, Qv);
    EXPECT_LT((Qv - expected).norm(), 1e-7 * (1 + expected.norm())) << "Q_v\n" << Qv << "\nLagrange\n" << expected;
    EXPECT_GT(expected.norm(), 1e-2) << "the check needs a non-trivial Q_v";
}

TEST(FfrfBody, QuadraticVelocityForcesAreLagrangesTermsOfTheMassMatrix) {
    const LumpedModes lumped;
    expect_lagrange_quadratic_velocity(*make_from_file(lumped.text())->body, 11);
    BeamKeys keys;
    expect_lagrange_quadratic_velocity(*make_beam(keys)->body, 12);
    keys.stiffening = true;
    expect_lagrange_quadratic_velocity(*make_beam(keys)->body, 13);
}

// ---------------------------------------------------------------- own derivatives
TEST(FfrfBody, FramesElasticAndGravityForcesAgreeWithFiniteDifferences) {
    const LumpedModes lumped;
    auto f = make_from_file(lumped.text());
    auto b = make_beam(BeamKeys{});
    for (const FlexibleBody* body : {f->body.get(), b->body.get()}) {
        Eigen::VectorXd q, v;
        random_state(*body, 21, 0.3, q, v);
        for (double xi : {0.0, 1.0, 2.0 / 3.0 + (body == f->body.get() ? 1.0 / 3.0 : 0.0)})
            test::expect_frame_derivatives(*body, q, v, xi, 1e-6);
        const int n = body->coordinates();
        const double h = 1e-6;
        Eigen::VectorXd Q(n), Qp(n), Qm(n);
        Eigen::MatrixXd dQ(n, n);
        body->elastic_forces(q, Q);
        body->elastic_jacobian(q, dQ);
        EXPECT_NEAR(-(body->strain_energy(q + h * v) - body->strain_energy(q - h * v)) / (2 * h), Q.dot(v),
                    1e-7 * (1 + Q.norm()));
        body->elastic_forces(q + h * v, Qp);
        body->elastic_forces(q - h * v, Qm);
        EXPECT_LT(((Qp - Qm) / (2 * h) - dQ * v).norm(), 1e-7 * (1 + dQ.norm()));
        const Vec3 g(0.3, -9.81, 0);
        body->gravity_forces(q, g, Q);
        EXPECT_NEAR(-(body->gravity_potential(q + h * v, g) - body->gravity_potential(q - h * v, g)) / (2 * h),
                    Q.dot(v), 1e-7 * (1 + Q.norm()));
    }
}

// ---------------------------------------------------------------- free-floating body
// M vdot = Q_v + Q_e, integrated by classical RK4 (the test's own) on y = [q, v]. With `pinned`
// the frame's origin is held at the world's origin and a rigid hub of inertia `hub` turns with
// the frame (a beam clamped to a free hub).
struct FreeBody {
    const FlexibleBody& body;
    bool pinned = false;
    double hub = 0.0;
    Eigen::MatrixXd mass(const Eigen::VectorXd& q) const {
        Eigen::MatrixXd M = mass_at(body, q);
        M(2, 2) += hub;
        return M;
    }
    Eigen::VectorXd rate(const Eigen::VectorXd& y) const {
        const int n = body.coordinates(), held = pinned ? 2 : 0;
        const Eigen::VectorXd q = y.head(n), v = y.tail(n);
        Eigen::VectorXd Qv(n), Qe(n);
        body.quadratic_velocity_forces(q, v, Qv);
        body.elastic_forces(q, Qe);
        const test::Reduced free(n, held);
        Eigen::VectorXd vdot = Eigen::VectorXd::Zero(n);
        free.put(free.take(mass(q)).lu().solve(free.take(Eigen::VectorXd(Qv + Qe))), vdot);
        Eigen::VectorXd ydot(2 * n);
        ydot << v, vdot;
        return ydot;
    }
    void rk4(Eigen::VectorXd& y, double h) const {
        const Eigen::VectorXd k1 = rate(y), k2 = rate(y + 0.5 * h * k1), k3 = rate(y + 0.5 * h * k2),
                              k4 = rate(y + h * k3);
        y += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    double energy(const Eigen::VectorXd& y) const {
        const int n = body.coordinates();
        const Eigen::VectorXd q = y.head(n), v = y.tail(n);
        return 0.5 * v.dot(mass(q) * v) + body.strain_energy(q);
    }
    // Linear momentum (M v over R) and angular momentum about the world's origin (the momentum
    // conjugate to theta plus R x the linear momentum): conserved with no external force; pinned,
    // only the angular momentum (the pin's force passes through the origin).
    Eigen::Vector3d momentum(const Eigen::VectorXd& y) const {
        const int n = body.coordinates();
        const Eigen::VectorXd p = mass(y.head(n)) * y.tail(n);
        if (pinned) return {0.0, 0.0, p[2]};
        return {p[0], p[1], p[2] + y[0] * p[1] - y[1] * p[0]};
    }
};

// The largest relative energy and momentum changes over `duration` at step h.
Eigen::Vector2d free_flight_drift(const FreeBody& free, double h, double duration) {
    const FlexibleBody& body = free.body;
    Eigen::VectorXd q, v;
    random_state(body, 31, 0.1, q, v);
    v[2] = 3.0;  // a fast spin, so that the frame and the modes exchange energy
    // deformations of a few per cent of the size: the stiffened M (-p^T Kg p in M_thetatheta,
    // second order in p) stays positive definite only while they are small (docs/plugin-sdk.md)
    const int m = body.coordinates() - 3;
    q.tail(m) *= 0.1;
    v.tail(m) *= 0.1;
    if (free.pinned) q.head<2>().setZero(), v.head<2>().setZero();
    Eigen::VectorXd y(2 * q.size());
    y << q, v;
    const double E0 = free.energy(y);
    const Eigen::Vector3d H0 = free.momentum(y);
    Eigen::Vector2d drift = Eigen::Vector2d::Zero();
    for (int s = 0; s < std::lround(duration / h); ++s) {
        free.rk4(y, h);
        drift[0] = std::max(drift[0], std::abs(free.energy(y) - E0) / E0);
        drift[1] = std::max(drift[1], (free.momentum(y) - H0).norm() / H0.norm());
    }
    return drift;
}

TEST(FfrfBody, FreeFloatingBodyConservesEnergyAndMomentum) {
    const LumpedModes lumped;
    auto f = make_from_file(lumped.text());
    BeamKeys keys;
    keys.modes = 3;
    auto b = make_beam(keys);
    keys.stiffening = true;
    auto s = make_beam(keys);
    // the free beam is stiff: with clamped modes the frame's turn and the modes nearly cancel
    // (M's least eigenvalue 9e-5, a free-free frequency near 250 rad/s), so its step is finer and
    // its drift is held to its order only, over a shorter run
    const struct {
        const char* what;
        FreeBody free;
        double h, duration, bound;
    } cases[] = {{"mode file, free", {*f->body}, 4e-3, 2.0, 1e-7},
                 {"beam, free", {*b->body}, 2e-4, 0.5, 1e-4},
                 {"beam on a hub", {*b->body, true, 1.0}, 5e-4, 2.0, 1e-7},
                 {"beam, stiffened, on a hub", {*s->body, true, 1.0}, 5e-4, 2.0, 1e-7}};
    for (const auto& c : cases) {
        const Eigen::Vector2d coarse = free_flight_drift(c.free, c.h, c.duration),
                              fine = free_flight_drift(c.free, c.h / 2, c.duration);
        std::printf("%s: relative energy drift %.2e -> %.2e (ratio %.1f), momentum %.2e\n", c.what, coarse[0],
                    fine[0], coarse[0] / fine[0], fine[1]);
        EXPECT_LT(fine[0], c.bound) << c.what;
        EXPECT_GT(coarse[0] / fine[0], 12.0) << c.what << ": RK4's order 4: the drift is the integrator's, not the model's";
        EXPECT_LT(fine[1], 10 * c.bound) << c.what;
    }
}

// ---------------------------------------------------------------- rotating beam
// At a constant spin Omega the modes obey Mff pddot = -(Kff + Omega^2 (Kg - Mff)) p (in-plane
// bending): the first frequency is omega^2 = omega_0^2 + (K_1 - 1) Omega^2 with K_1 the
// Southwell coefficient of a uniform cantilever with no hub offset, 1.1933 (Wright, Smith,
// Thresher and Wang, J. Appl. Mech. 49 (1982) 197-202; 1.193363 by the test author's own
// quadrature of the exact first mode). Linearized from the body's own Q_v (linear in p).
TEST(FfrfBody, GeometricStiffeningGivesTheSouthwellCoefficient) {
    BeamKeys keys;
    keys.elements = 40, keys.stiffening = true;
    auto b = make_beam(keys);
    const FlexibleBody& body = *b->body;
    const int n = body.coordinates();
    const double omega0 = 1.875104068711961 * 1.875104068711961, spin = 0.1 * omega0;
    Eigen::VectorXd q = body.initial_coordinates(), v = Eigen::VectorXd::Zero(n), Q(n), Q0(n), Qe(n);
    v[2] = spin;
    body.quadratic_velocity_forces(q, v, Q0);
    Eigen::MatrixXd stiffness(n - 3, n - 3), dQ(n, n);
    body.elastic_jacobian(q, dQ);
    for (int i = 0; i < n - 3; ++i) {
        Eigen::VectorXd qi = q;
        qi[3 + i] += 1.0;
        body.quadratic_velocity_forces(qi, v, Q);
        stiffness.col(i) = -dQ.col(3 + i).tail(n - 3) - (Q - Q0).tail(n - 3);
    }
    const Eigen::MatrixXd M = mass_at(body, q).bottomRightCorner(n - 3, n - 3);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (stiffness + stiffness.transpose()), M);
    const double southwell = 1.0 + (eig.eigenvalues()[0] - omega0 * omega0) / (spin * spin);
    std::printf("Southwell coefficient %.6f\n", southwell);
    EXPECT_NEAR(southwell, 1.193363, 1e-3);
}

// Kane, Ryan and Banerjee's spin-up (J. Guidance 10 (1987) 139-151): the frame's angle is
// prescribed, thetadot = (Omega / T) (t - T / (2 pi) sin(2 pi t / T)) up to T = 15 s, then Omega.
// The beam: L = 10 m, EI = 14000 N m^2, rho A = 1.2 kg/m (omega_1 = 3.80 rad/s). The modes obey
// Mff pddot = Q_f - M_ftheta thetaddot (the frame's origin fixed). Returns the largest |tip
// deflection| (the tip's y in the frame's axes) up to t_end.
double spin_up_tip_deflection(bool stiffening, double Omega, double t_end) {
    BeamKeys keys;
    keys.length = 10, keys.elements = 10, keys.stiffening = stiffening;
    keys.modulus = 7e10, keys.second_moment = 2e-7, keys.area = 4e-4, keys.density = 3000;
    auto b = make_beam(keys);
    const FlexibleBody& body = *b->body;
    const int n = body.coordinates(), m = n - 3;
    const double T = 15.0, pi = std::acos(-1.0);
    auto spin = [&](double t, double& w, double& wdot, double& angle) {
        if (t >= T) {
            w = Omega, wdot = 0, angle = Omega * (T / 2) + Omega * (t - T);
            return;
        }
        const double s = 2 * pi * t / T;
        w = Omega / T * (t - T / (2 * pi) * std::sin(s));
        wdot = Omega / T * (1 - std::cos(s));
        angle = Omega / T * (t * t / 2 + (T / (2 * pi)) * (T / (2 * pi)) * (std::cos(s) - 1));
    };
    auto rate = [&](double t, const Eigen::VectorXd& y) {
        Eigen::VectorXd q = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Zero(n), Q(n), Qe(n);
        double wdot = 0;
        spin(t, v[2], wdot, q[2]);
        q.tail(m) = y.head(m), v.tail(m) = y.tail(m);
        body.quadratic_velocity_forces(q, v, Q);
        body.elastic_forces(q, Qe);
        const Eigen::MatrixXd M = mass_at(body, q);
        Eigen::VectorXd ydot(2 * m);
        ydot << y.tail(m), M.bottomRightCorner(m, m).lu().solve(Eigen::VectorXd((Q + Qe).tail(m) - M.col(2).tail(m) * wdot));
        return ydot;
    };
    const double L = 10.0;
    double largest = 0, h = 5e-3;  // omega_4 h = 0.65, well inside RK4's stability
    Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * m);
    for (int s = 0; s < std::lround(t_end / h); ++s) {
        const double t = s * h;
        const Eigen::VectorXd k1 = rate(t, y), k2 = rate(t + h / 2, y + h / 2 * k1), k3 = rate(t + h / 2, y + h / 2 * k2),
                              k4 = rate(t + h, y + h * k3);
        y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        Eigen::VectorXd q = Eigen::VectorXd::Zero(n);
        q.tail(m) = y.head(m);
        MaterialPoint tip;
        body.point(q, Eigen::VectorXd::Zero(n), &L, tip);  // theta = 0: the frame's axes are the world's
        largest = std::max(largest, std::abs(tip.r.y()));
        if (largest > 10 * L) break;  // diverged
    }
    return largest;
}

TEST(FfrfBody, RotatingBeamStaysBoundedWithGeometricStiffeningAndDivergesWithout) {
    // The peak inertial load rho A thetaddot_max x (thetaddot_max = 2 Omega / T) bends the
    // non-rotating cantilever by 11 q L^4 / (120 EI) = 0.42 m at Omega = 4; a dynamic load at most
    // doubles that.
    const double stiffened = spin_up_tip_deflection(true, 4.0, 25.0);
    const double linear = spin_up_tip_deflection(false, 4.0, 25.0);
    const double below_critical = spin_up_tip_deflection(false, 3.0, 25.0);
    std::printf("largest tip deflection: stiffened %.4f m, linear %.4g m at 4 rad/s; linear %.4f m at 3 rad/s\n",
                stiffened, linear, below_critical);
    EXPECT_LT(stiffened, 2 * 0.42);
    EXPECT_GT(linear, 10.0) << "above omega_1 = 3.80 rad/s the linear model diverges (deflection beyond L)";
    EXPECT_LT(below_critical, 10.0) << "below omega_1 the linear model stays bounded";
}

// ---------------------------------------------------------------- bad input
void expect_refusal(const std::string& message, std::initializer_list<const char*> parts) {
    for (const char* part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
}

TEST(FfrfBody, BadInputIsRefusedNamingTheBody) {
    auto beam_with = [](auto change) {
        return test::input_error_of([&] {
            BeamKeys k;
            change(k);
            make_beam(k);
        });
    };
    expect_refusal(beam_with([](BeamKeys& k) { k.modulus = 0; }), {"body 'beam'", "'modulus' must be positive", "beam.yaml:3"});
    expect_refusal(beam_with([](BeamKeys& k) { k.area = -1; }), {"body 'beam'", "'area' must be positive"});
    expect_refusal(beam_with([](BeamKeys& k) { k.length = 0; }), {"body 'beam'", "zero length"});
    expect_refusal(beam_with([](BeamKeys& k) { k.elements = 0; }), {"body 'beam'", "needs two nodes"});
    expect_refusal(beam_with([](BeamKeys& k) { k.elements = 1, k.modes = 4; }), {"body 'beam'", "4 modes need at least 2 elements"});
    const LumpedModes lumped;
    std::string text = lumped.text();
    expect_refusal(test::input_error_of([] { make_from_file("", "absent.txt"); }), {"body 'beam'", "cannot open the mode file"});
    std::string bad_mass = test::replaced(text, "mode " + [&] {
        std::ostringstream o;
        o.precision(17);
        o << lumped.modal_mass(0);
        return o.str();
    }(), "mode -1");
    expect_refusal(test::input_error_of([&] { make_from_file(bad_mass, "bad_mass.txt"); }),
                   {"body 'beam'", "bad_mass.txt:6", "modal mass must be positive"});
    expect_refusal(test::input_error_of([&] { make_from_file(test::replaced(text, "1 0.20000000000000001 2", "1 zero 2"), "bad_line.txt"); }),
                   {"body 'beam'", "bad_line.txt:4", "'zero' is not a number"});
    expect_refusal(test::input_error_of([&] { make_from_file("nodes 2\n0 0 1\n1 0 1\nmode 1 1\n0 1 0\n", "short.txt"); }),
                   {"body 'beam'", "short.txt:5", "the file ends where"});
    expect_refusal(test::input_error_of([&] {
                       const auto dir = test::scratch("ffrf_body");
                       test::write_text(dir / "modes.txt", lumped.text());
                       test::make_body("ffrf_body", {{"mode_file", scalar_param((dir / "modes.txt").string())},
                                                     {"geometric_stiffening", scalar_param("true")}});
                   }),
                   {"body 'beam'", "geometric stiffening needs the beam's slopes"});
    auto b = make_beam(BeamKeys{});
    const double inside = 1.0, beyond = 1.001, between_nodes = 0.5, last_node = 2.0;
    EXPECT_NO_THROW(b->body->check_material_point(&inside));
    EXPECT_THROW(b->body->check_material_point(&beyond), InputError);
    auto f = make_from_file(lumped.text());
    EXPECT_NO_THROW(f->body->check_material_point(&last_node));
    EXPECT_THROW(f->body->check_material_point(&between_nodes), InputError);
    const double past_last_node = 3.0;
    EXPECT_THROW(f->body->check_material_point(&past_last_node), InputError);
}

}  // namespace
}  // namespace mbd
