// The planar ANCF cable body plugin (plugins/bodies/ancf, sdk body.hpp) against independent
// oracles: Euler-Bernoulli cantilever frequencies, the linear tip deflection P L^3 / (3 EI), the
// elastica by elliptic integrals, energy conservation of a flexible pendulum, finite differences
// of its own derivatives, and refusals of bad input naming the body.
#include "support/flexible_body.hpp"

#include <mbd/integrator.hpp>
#include <mbd/sdk/body.hpp>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace mbd {
namespace {

// ---------------------------------------------------------------- a cable from keys
using test::number_param;
using test::Reduced;

struct CableKeys {
    double length = 1.0;
    int elements = 4;
    double modulus = 1e6, area = 1.0, second_moment = 1e-6, density = 1.0;  // EI = 1, rho A = 1
    int axial_points = 0;  // 0: the key left out
};

using Cable = test::BodyFromKeys;

std::unique_ptr<Cable> make_cable(const CableKeys& k) {
    std::map<std::string, Param> fields = {{"from", test::list_param({0, 0})},
                                           {"to", test::list_param({k.length, 0})},
                                           {"elements", number_param(k.elements)},
                                           {"modulus", number_param(k.modulus)},
                                           {"area", number_param(k.area)},
                                           {"second_moment", number_param(k.second_moment)},
                                           {"density", number_param(k.density)}};
    if (k.axial_points) fields["axial_points"] = number_param(k.axial_points);
    return test::make_body("ancf_cable", fields);
}

// Static equilibrium Q_e(q) + F = 0 on the free coordinates, the load in `steps` equal increments,
// Newton-Raphson at each.
Eigen::VectorXd equilibrium(const FlexibleBody& body, const Reduced& red, const Eigen::VectorXd& F, int steps) {
    const int n = body.coordinates();
    Eigen::VectorXd q = body.initial_coordinates(), Q(n);
    Eigen::MatrixXd dQ(n, n);
    for (int s = 1; s <= steps; ++s) {
        const Eigen::VectorXd load = F * (double(s) / steps);
        for (int it = 0;; ++it) {
            if (it == 30) {
                ADD_FAILURE() << "Newton did not converge at load step " << s;
                return q;
            }
            body.elastic_forces(q, Q);
            body.elastic_jacobian(q, dQ);
            const Eigen::VectorXd dq = -red.take(dQ).lu().solve(red.take(Eigen::VectorXd(Q + load)));
            Eigen::VectorXd full = Eigen::VectorXd::Zero(n);
            red.put(dq, full);
            q += full;
            if (dq.norm() < 1e-13) break;  // quadratic convergence: the next step is round-off
        }
    }
    return q;
}

// ---------------------------------------------------------------- natural frequencies
// The two lowest frequencies of a cantilever (node 0 clamped) from K phi = omega^2 M phi.
Eigen::Vector2d cantilever_frequencies(int elements) {
    CableKeys k;
    k.elements = elements;
    auto c = make_cable(k);
    const int n = c->body->coordinates();
    const Eigen::VectorXd q = c->body->initial_coordinates();
    Eigen::MatrixXd M, dQ(n, n);
    c->body->mass_matrix(q, M);
    c->body->elastic_jacobian(q, dQ);
    const Reduced red(n, 4);
    const Eigen::MatrixXd K = -red.take(dQ);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, red.take(M));
    return eig.eigenvalues().head<2>().cwiseSqrt();
}

TEST(AncfCable, CantileverFrequenciesConvergeToEulerBernoulli) {
    // omega_i = (beta_i L)^2 sqrt(EI / (rho A L^4)) with EI = rho A = L = 1; the first axial
    // frequency (pi / 2) sqrt(EA / rho A) = 1571 lies far above both.
    const double beta[2] = {1.875104068711961, 4.694091132974175};
    double previous[2] = {0, 0};
    for (int N : {1, 2, 4, 8, 16}) {
        const Eigen::Vector2d omega = cantilever_frequencies(N);
        for (int i = 0; i < 2; ++i) {
            const double exact = beta[i] * beta[i];
            const double error = std::abs(omega[i] - exact) / exact;
            EXPECT_GT(omega[i], exact * (1 - 1e-12)) << "Rayleigh-Ritz bounds from above";
            if (previous[i] > 0 && N >= 4) {
                // cubic Hermite elements: frequency error O(h^4) (Strang and Fix), ratio 16 per halving
                const double rate = std::log2(previous[i] / error);
                std::printf("N = %2d  omega_%d relative error %.3e  rate %.2f\n", N, i + 1, error, rate);
                if (N >= 8) {  // asymptotic from 8 elements on (mode 2 with 2 elements is not yet)
                    EXPECT_GT(rate, 3.6) << "mode " << i + 1 << ", N = " << N;
                    EXPECT_LT(rate, 4.4) << "mode " << i + 1 << ", N = " << N;
                }
            }
            previous[i] = error;
        }
    }
    EXPECT_LT(previous[0], 1e-6);
    EXPECT_LT(previous[1], 1e-5);
}

// ---------------------------------------------------------------- static tip loads
Eigen::Vector2d tip_under_load(const FlexibleBody& body, double P, int steps) {
    const int n = body.coordinates();
    Eigen::VectorXd F = Eigen::VectorXd::Zero(n);
    F[n - 3] = -P;  // the last node's y
    const Eigen::VectorXd q = equilibrium(body, Reduced(n, 4), F, steps);
    return q.segment<2>(n - 4);
}

TEST(AncfCable, SmallTipLoadGivesLinearBeamTheory) {
    auto c = make_cable({1.0, 4});
    const double P = 1e-4;  // P L^2 / EI = 1e-4: the geometric nonlinearity is O(1e-8) of the deflection
    const Eigen::Vector2d tip = tip_under_load(*c->body, P, 1);
    EXPECT_NEAR(-tip.y(), P / 3.0, 1e-6 * P / 3.0);  // P L^3 / (3 EI)
}

TEST(AncfCable, SmallTipLoadGivesTheLinearTipSlope) {
    auto c = make_cable({1.0, 2});
    const FlexibleBody& body = *c->body;
    const int n = body.coordinates();
    const double P = 1e-4;
    Eigen::VectorXd F = Eigen::VectorXd::Zero(n);
    F[n - 3] = -P;
    const Eigen::VectorXd q = equilibrium(body, Reduced(n, 4), F, 1);
    const double L = 1.0;
    MaterialFrame tip;
    body.frame(q, Eigen::VectorXd::Zero(n), &L, tip);
    EXPECT_NEAR(-tip.planar.theta, P / 2.0, 1e-6 * P / 2.0);  // P L^2 / (2 EI)
}

TEST(AncfCable, RigidMotionsStoreNoEnergyAndCarryTheWholeMass) {
    CableKeys keys{2.0, 3};
    keys.density = 7.0;  // rho A L = 14
    auto c = make_cable(keys);
    const FlexibleBody& body = *c->body;
    const int n = body.coordinates();
    // rotate the straight configuration by 0.7 rad about the origin and move it by (0.3, -1.2)
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
    Eigen::VectorXd q = body.initial_coordinates(), Q(n);
    for (int k = 0; k < n; k += 4) {
        q.segment<2>(k) = R * q.segment<2>(k) + Eigen::Vector2d(0.3, -1.2);
        q.segment<2>(k + 2) = R * q.segment<2>(k + 2);
    }
    EXPECT_NEAR(body.strain_energy(q), 0.0, 1e-12);
    body.elastic_forces(q, Q);
    EXPECT_LT(Q.norm(), 1e-9);
    // a unit translation along x (ones on the nodes' x, zero slopes) has kinetic energy m / 2
    Eigen::MatrixXd M;
    body.mass_matrix(q, M);
    Eigen::VectorXd ux = Eigen::VectorXd::Zero(n);
    for (int k = 0; k < n; k += 4) ux[k] = 1.0;
    EXPECT_NEAR(ux.dot(M * ux), 14.0, 1e-12);
    // gravity on it: the weight m g, along g
    body.gravity_forces(q, Vec3(0, -9.81, 0), Q);
    Eigen::VectorXd uy = Eigen::VectorXd::Zero(n);
    for (int k = 1; k < n; k += 4) uy[k] = 1.0;
    EXPECT_NEAR(Q.dot(uy), -14.0 * 9.81, 1e-10);
    EXPECT_NEAR(Q.dot(ux), 0.0, 1e-12);
}

// The tip of a cantilever's elastica under a dead tip load P (alpha^2 = P L^2 / EI) by elliptic
// integrals: with k^2 = P / EI, p^2 = (1 + sin phi0) / 2 (phi0 the tip's slope angle) and
// sin phi1 = 1 / (p sqrt 2): k L = K(p) - F(phi1, p), x_tip = 2 p cos(phi1) / k,
// y_tip (down) = L - 2 (E(p) - E(phi1, p)) / k.
Eigen::Vector2d elastica_tip(double alpha2, double L) {
    namespace bm = boost::math;
    const double alpha = std::sqrt(alpha2);
    auto length_residual = [&](double p) {
        const double phi1 = std::asin(1.0 / (p * std::sqrt(2.0)));
        return bm::ellint_1(p) - bm::ellint_1(p, phi1) - alpha;
    };
    double lo = 1.0 / std::sqrt(2.0) + 1e-15, hi = 1.0 - 1e-15;
    for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (length_residual(mid) < 0 ? lo : hi) = mid;
    }
    const double p = 0.5 * (lo + hi), phi1 = std::asin(1.0 / (p * std::sqrt(2.0))), k = alpha / L;
    return {2.0 * p * std::cos(phi1) / k, L - 2.0 * (bm::ellint_2(p) - bm::ellint_2(p, phi1)) / k};
}

TEST(AncfCable, ElasticaOracleMatchesBisshoppDrucker) {
    // Bisshopp and Drucker (1945), Quart. Appl. Math. 3: P L^2 / EI = 1 gives a vertical tip
    // deflection 0.30172 L and a horizontal one 0.05643 L; the small-load limit is P L^3 / (3 EI).
    const Eigen::Vector2d tip = elastica_tip(1.0, 1.0);
    EXPECT_NEAR(tip.y(), 0.30172, 1e-5);
    EXPECT_NEAR(1.0 - tip.x(), 0.05643, 1e-5);
    EXPECT_NEAR(elastica_tip(1e-4, 1.0).y(), 1e-4 / 3.0, 1e-10);
}

TEST(AncfCable, LargeTipLoadMatchesTheElastica) {
    CableKeys keys{1.0, 16};
    keys.modulus = 1e8;  // nearly inextensible: EA / (EI / L^2) = 1e8, axial strain <= 1e-7
    keys.second_moment = 1e-8;
    keys.axial_points = 2;  // the locking remedy: with 5 points this mesh is 6.6e-4 too stiff at P L^2 / EI = 10
    auto c = make_cable(keys);
    for (double alpha2 : {1.0, 3.0, 10.0}) {
        const Eigen::Vector2d exact = elastica_tip(alpha2, 1.0);
        const Eigen::Vector2d tip = tip_under_load(*c->body, alpha2, 10);
        EXPECT_NEAR(tip.x(), exact.x(), 1e-4) << "P L^2 / EI = " << alpha2;
        EXPECT_NEAR(-tip.y(), exact.y(), 1e-4) << "P L^2 / EI = " << alpha2;
    }
}

// ---------------------------------------------------------------- own derivatives
TEST(AncfCable, DerivativesAgreeWithFiniteDifferences) {
    auto c = make_cable({2.0, 3});
    const FlexibleBody& body = *c->body;
    const int n = body.coordinates();
    std::mt19937 rng(5);
    std::normal_distribution<double> gauss;
    Eigen::VectorXd q = body.initial_coordinates(), v(n), Q(n), Qp(n), Qm(n);
    for (int k = 0; k < n; ++k) q[k] += 0.05 * gauss(rng), v[k] = gauss(rng);
    Eigen::MatrixXd dQ(n, n);
    body.elastic_forces(q, Q);
    body.elastic_jacobian(q, dQ);
    const double h = 1e-6;
    for (int k = 0; k < n; ++k) {
        Eigen::VectorXd qp = q, qm = q;
        qp[k] += h, qm[k] -= h;
        EXPECT_NEAR(-(body.strain_energy(qp) - body.strain_energy(qm)) / (2 * h), Q[k], 1e-6 * (1 + Q.norm()));
        body.elastic_forces(qp, Qp);
        body.elastic_forces(qm, Qm);
        EXPECT_LT(((Qp - Qm) / (2 * h) - dQ.col(k)).norm(), 1e-6 * (1 + dQ.norm())) << "column " << k;
    }
    // the frame at a material point: velocity G v, acceleration G vdot + a
    test::expect_frame_derivatives(body, q, v, 1.3, 1e-5);
    const Vec3 g(0.3, -9.81, 0);
    body.gravity_forces(q, g, Q);
    EXPECT_NEAR(-(body.gravity_potential(q + h * v, g) - body.gravity_potential(q - h * v, g)) / (2 * h), Q.dot(v),
                1e-8 * (1 + std::abs(Q.dot(v))));
}

// ---------------------------------------------------------------- joints on material frames
// A joint plugin evaluated, unchanged, on a material frame of the cable and mapped to the cable's
// coordinates by the chain rule (sdk body.hpp map_frame_rows): along a motion q(t) = q0 + v t +
// vdot t^2 / 2, its residual's rates are J v (C_t = 0) and J vdot - gamma (book Eq. 3.124).
struct FrameJointRows {
    Eigen::VectorXd C, gamma;
    Eigen::MatrixXd J;
};
FrameJointRows joint_on_frame(const Joint& joint, const FlexibleBody& body, double x, const Eigen::VectorXd& q,
                              const Eigen::VectorXd& v) {
    MaterialFrame frame;
    body.frame(q, v, &x, frame);
    PlanarBody ground;
    ground.ground = true;
    BodyStates states;
    states.planar_bodies = {&ground, &frame.planar};
    ConstraintEval eval;
    eval.resize(joint.rows(), 6);
    joint.evaluate(states, eval);
    FrameJointRows rows{eval.C, eval.gamma, Eigen::MatrixXd(joint.rows(), body.coordinates())};
    map_frame_rows(eval.J.rightCols(3), frame, rows.J, rows.gamma);
    return rows;
}

TEST(AncfCable, JointsOnMaterialFramesKeepTheirMeaningByTheChainRule) {
    auto c = make_cable({1.0, 3});
    const FlexibleBody& body = *c->body;
    const int n = body.coordinates();
    std::mt19937 rng(17);
    std::normal_distribution<double> gauss;
    Eigen::VectorXd q0 = body.initial_coordinates(), v(n), a(n);
    for (int k = 0; k < n; ++k) q0[k] += 0.05 * gauss(rng), v[k] = gauss(rng), a[k] = gauss(rng);
    for (const char* type : {"revolute", "fixed"}) {
        for (double x : {0.0, 0.37}) {  // at node 0 (a pin, a clamp) and inside the first element
            BodyInfo ground_info, frame_info;
            ground_info.name = "ground", ground_info.ground = true;
            frame_info.name = "beam";
            MaterialFrame initial;
            body.frame(body.initial_coordinates(), Eigen::VectorXd::Zero(n), &x, initial);
            frame_info.position << initial.planar.R, 0.0;
            frame_info.angle = initial.planar.theta;
            Marker on_ground, on_frame;
            on_frame.u_bar = Vec3(0.1, 0.05, 0);  // a joint point offset from the frame's origin
            on_ground.u_bar = frame_info.position + Vec3(0.1, 0.05, 0);
            JointSpec spec{"pin", type, Dimension::Planar, {ground_info, frame_info}, {on_ground, on_frame}, Params()};
            auto joint = test::shared_registry().create_joint(spec, "test");
            const double h = 1e-5;
            auto at = [&](double t) { return Eigen::VectorXd(q0 + v * t + 0.5 * a * t * t); };
            auto vel = [&](double t) { return Eigen::VectorXd(v + a * t); };
            const FrameJointRows now = joint_on_frame(*joint, body, x, q0, v);
            const FrameJointRows ahead = joint_on_frame(*joint, body, x, at(h), vel(h));
            const FrameJointRows behind = joint_on_frame(*joint, body, x, at(-h), vel(-h));
            const Eigen::VectorXd Cdot = (ahead.C - behind.C) / (2 * h);
            const Eigen::VectorXd Cddot = (ahead.C - 2 * now.C + behind.C) / (h * h);
            EXPECT_LT((Cdot - now.J * v).norm(), 1e-7 * (1 + Cdot.norm())) << type << " at x = " << x;
            EXPECT_LT((Cddot - (now.J * a - now.gamma)).norm(), 1e-4 * (1 + Cddot.norm())) << type << " at x = " << x;
        }
    }
}

// ---------------------------------------------------------------- flexible pendulum
// Pinned at node 0 (its position held), released horizontal under gravity: M vdot = Q_e + Q_g.
class PinnedCable : public OdeProblem {
public:
    PinnedCable(const FlexibleBody& body, const Vec3& g)
        : body_(body), red_(body.coordinates(), 2), g_(g), q_(body.initial_coordinates()), Q_(q_.size()),
          Qg_(q_.size()) {
        Eigen::MatrixXd M;
        body.mass_matrix(q_, M);
        mass_ = red_.take(M);
        factor_.compute(mass_);  // constant: factored once
        body.gravity_forces(q_, g, Qg_);
    }
    int size() const override { return 2 * red_.size(); }
    void rhs(double, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override {
        const int m = red_.size();
        red_.put(y.head(m), q_);
        body_.elastic_forces(q_, Q_);
        ydot.resize(2 * m);
        ydot.head(m) = y.tail(m);
        ydot.tail(m) = factor_.solve(red_.take(Eigen::VectorXd(Q_ + Qg_)));
    }
    bool project(double, Eigen::VectorXd&) override { return true; }  // nothing to project: no constraints left
    double energy(const Eigen::VectorXd& y) {
        const int m = red_.size();
        red_.put(y.head(m), q_);
        return 0.5 * y.tail(m).dot(mass_ * y.tail(m)) + body_.strain_energy(q_) + body_.gravity_potential(q_, g_);
    }
    Eigen::VectorXd y0() const {
        return (Eigen::VectorXd(2 * red_.size()) << red_.take(body_.initial_coordinates()),
                Eigen::VectorXd::Zero(red_.size()))
            .finished();
    }
    int tip_y_index() const { return red_.size() - 3; }  // the last node's y among the free coordinates

private:
    const FlexibleBody& body_;
    Reduced red_;
    Vec3 g_;
    Eigen::VectorXd q_, Q_, Qg_;
    Eigen::MatrixXd mass_;
    Eigen::LLT<Eigen::MatrixXd> factor_;
};

TEST(AncfCable, FlexiblePendulumConservesEnergy) {
    CableKeys keys{1.0, 4};
    keys.modulus = 1e6, keys.area = 1e-3, keys.second_moment = 1e-6, keys.density = 1000;  // EA 1000, EI 1, 1 kg/m
    auto c = make_cable(keys);
    const double scale = 1.0 * 9.81 * 0.5;  // m g L / 2, the potential energy the swing exchanges
    for (double tol : {1e-6, 1e-8}) {
        PinnedCable problem(*c->body, Vec3(0, -9.81, 0));
        IntegratorSettings settings;
        settings.tolerance = tol;
        auto integrator = make_integrator("dopri5", settings);
        Eigen::VectorXd y = problem.y0();
        const double E0 = problem.energy(y);
        double drift = 0.0, lowest_tip = 0.0;
        std::vector<double> times;
        for (int k = 1; k <= 100; ++k) times.push_back(0.05 * k);  // 5 s, about three swings
        IntegratorStats stats;
        integrator->integrate(problem, 0.0, y, times, [&](double, const Eigen::VectorXd& yt) {
            drift = std::max(drift, std::abs(problem.energy(yt) - E0));
            lowest_tip = std::min(lowest_tip, yt[problem.tip_y_index()]);
            return true;
        }, stats);
        std::printf("tolerance %.0e: energy drift %.3e of m g L / 2 over 5 s, %ld steps\n", tol, drift / scale,
                    stats.steps);
        EXPECT_LT(drift, tol * scale) << "tolerance " << tol;  // measured: about 1e-2 of it
        EXPECT_LT(lowest_tip, -0.8) << "the pendulum swings through the bottom";
    }
}

// ---------------------------------------------------------------- bad input
std::string refusal(const CableKeys& keys, bool zero_length = false) {
    try {
        CableKeys k = keys;
        if (zero_length) k.length = 0.0;
        make_cable(k);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(AncfCable, BadInputIsRefusedNamingTheBody) {
    CableKeys k;
    k.modulus = 0;
    EXPECT_NE(refusal(k).find("body 'beam'"), std::string::npos) << refusal(k);
    EXPECT_NE(refusal(k).find("'modulus' must be positive"), std::string::npos) << refusal(k);
    k = {};
    k.area = -1;
    EXPECT_NE(refusal(k).find("'area' must be positive"), std::string::npos) << refusal(k);
    k = {};
    k.second_moment = -1;
    EXPECT_NE(refusal(k).find("'second_moment' must be positive"), std::string::npos) << refusal(k);
    k = {};
    EXPECT_NE(refusal(k, true).find("zero length"), std::string::npos) << refusal(k, true);
    EXPECT_NE(refusal(k, true).find("body 'beam'"), std::string::npos) << refusal(k, true);
    k.elements = 0;
    EXPECT_NE(refusal(k).find("needs two nodes"), std::string::npos) << refusal(k);
    EXPECT_NE(refusal(k).find("beam.yaml:3"), std::string::npos) << refusal(k);
    // a material point beyond the end of the beam
    auto c = make_cable({1.0, 2});
    const double inside = 1.0, beyond = 1.001;
    EXPECT_NO_THROW(c->body->check_material_point(&inside));
    EXPECT_THROW(c->body->check_material_point(&beyond), InputError);
}

}  // namespace
}  // namespace mbd
