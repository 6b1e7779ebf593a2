// Issue 38: the stepping Simulator (core/include/mbd/simulator.hpp). Oracles: an LQR
// cart-pole whose gain is computed here from a hand linearisation (Riccati equation solved
// here) and whose closed loop is integrated here on the closed-form equations; the whole
// run of simulate(); a built-in spring-damper; simulate()'s located events.
#include "support/test_support.hpp"

#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>
#include <mbd/simulator.hpp>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace {

using Eigen::Matrix4d;
using Eigen::Vector4d;
using Eigen::VectorXd;
using mbd::test::scene;

// --- the cart-pole of issue 38: cart M = 1 kg on a prismatic joint along x, pole a uniform
// rod m = 0.1 kg, l = 1 m pinned at its lower end to the cart, g = 9.81. theta: the pole
// from upright, positive towards +x (the pole's body angle is pi/2 - theta from world x).
constexpr double kM = 1.0, km = 0.1, kl = 1.0, kg = 9.81, kPi = 3.14159265358979323846;
constexpr double kTheta0 = 5.0 * kPi / 180.0, kPeriod = 0.01;

std::string cart_pole_yaml(const std::string& force) {
    const double lc = 0.5 * kl;
    std::ostringstream y;
    y << "name: cart-pole\ndimension: planar\ngravity: [0, " << -kg << "]\nbodies:\n"
      << "  - {name: cart, mass: " << kM << ", inertia: 0.01, position: [0, 0]}\n"
      << "  - {name: pole, mass: " << km << ", inertia: " << mbd::test::g17(km * kl * kl / 12.0)
      << ", position: [" << mbd::test::g17(lc * std::sin(kTheta0)) << ", " << mbd::test::g17(lc * std::cos(kTheta0))
      << "], angle: " << mbd::test::g17(0.5 * kPi - kTheta0) << "}\n"
      << "joints:\n"
      << "  - {name: rail, type: prismatic, bodies: [ground, cart], point: [0, 0], axis: [1, 0]}\n"
      << "  - {name: pin, type: revolute, bodies: [cart, pole], point: [0, 0]}\n"
      << "forces:\n  - {name: push, type: point_force, body: cart, force: [" << force << ", 0]}\n";
    return y.str();
}

// (x, theta, xdot, thetadot) of the scene's state.
Vector4d cart_pole_state(const mbd::State& s) {
    return {s.q[0], 0.5 * kPi - s.q[5], s.v[0], -s.v[5]};
}

// Lagrange's equations of the cart-pole, by hand (T = 1/2 (M+m) xdot^2 + m lc cos(th) xdot thdot
// + 1/2 I thdot^2, I = m l^2 / 3 about the pin; V = m g lc cos(th)):
//   (M + m) xdd + m lc cos(th) thdd - m lc sin(th) thd^2 = F
//   m lc cos(th) xdd + I thdd - m g lc sin(th) = 0
Vector4d cart_pole_rate(const Vector4d& s, double F) {
    const double lc = 0.5 * kl, I = km * kl * kl / 3.0, c = std::cos(s[1]), sn = std::sin(s[1]);
    Eigen::Matrix2d A;
    A << kM + km, km * lc * c, km * lc * c, I;
    const Eigen::Vector2d b(F + km * lc * sn * s[3] * s[3], km * kg * lc * sn);
    const Eigen::Vector2d acc = A.lu().solve(b);
    return {s[2], s[3], acc[0], acc[1]};
}

// The LQR gain K (F = -K s) of the linearisation at upright, Q = diag(1, 10, 1, 1), R = 0.1,
// from the continuous algebraic Riccati equation by the stable invariant subspace of the
// Hamiltonian matrix [A, -B R^-1 B^T; -Q, -A^T] (X = U2 U1^-1).
Eigen::RowVector4d lqr_gain() {
    const double lc = 0.5 * kl, I = km * kl * kl / 3.0;
    Eigen::Matrix2d Mm;
    Mm << kM + km, km * lc, km * lc, I;
    const Eigen::Matrix2d Minv = Mm.inverse();
    Matrix4d A = Matrix4d::Zero();
    A(0, 2) = A(1, 3) = 1.0;
    A.block<2, 1>(2, 1) = Minv * Eigen::Vector2d(0.0, km * kg * lc);  // d/dtheta of the gravity moment
    Vector4d B = Vector4d::Zero();
    B.tail<2>() = Minv * Eigen::Vector2d(1.0, 0.0);
    const Matrix4d Q = Eigen::Vector4d(1, 10, 1, 1).asDiagonal();
    const double R = 0.1;
    Eigen::Matrix<double, 8, 8> H;
    H << A, -(B * B.transpose()) / R, -Q, -A.transpose();
    Eigen::EigenSolver<Eigen::Matrix<double, 8, 8>> eig(H);
    Eigen::Matrix<std::complex<double>, 8, 4> U;
    int k = 0;
    for (int i = 0; i < 8; ++i)
        if (eig.eigenvalues()[i].real() < 0.0) U.col(k++) = eig.eigenvectors().col(i);
    EXPECT_EQ(k, 4);
    const Matrix4d X = (U.bottomRows<4>() * U.topRows<4>().inverse()).real();
    const Matrix4d residual = A.transpose() * X + X * A - X * B * B.transpose() * X / R + Q;
    EXPECT_LT(residual.cwiseAbs().maxCoeff(), 1e-9) << "the Riccati solution";
    return (B.transpose() * X) / R;
}

mbd::SimulationSettings quiet(const std::string& integrator, double tolerance, double step, double t_end) {
    mbd::SimulationSettings s;
    s.integrator = integrator;
    s.integration.tolerance = tolerance;
    s.integration.step = step;
    s.t_end = t_end;
    s.progress = false;
    s.messages = mbd::MessageLog::silent();
    return s;
}

// The closed loop through set_input every period (zero-order hold) to t_end: the forces set,
// and the pole angle after each period.
struct ClosedLoop {
    std::vector<double> forces, theta;
};
ClosedLoop run_closed_loop(const mbd::Model& model, const mbd::SimulationSettings& settings) {
    const Eigen::RowVector4d K = lqr_gain();
    mbd::Simulator sim(model, mbd::test::shared_registry(), settings);
    ClosedLoop loop;
    const int periods = static_cast<int>(std::lround(settings.t_end / kPeriod));
    for (int k = 0; k < periods; ++k) {
        const double F = -(K * cart_pole_state(sim.state()))(0);
        sim.set_input("force", F);
        loop.forces.push_back(F);
        sim.advance_to((k + 1) * kPeriod);
        loop.theta.push_back(cart_pole_state(sim.state())[1]);
    }
    EXPECT_NEAR(sim.time(), settings.t_end, 1e-12);
    return loop;
}

// The recorded forces as a piecewise-constant time function of the scene.
std::string steps_function(const std::vector<double>& forces) {
    std::ostringstream table;
    table << "{type: steps, table: [";
    for (size_t k = 0; k < forces.size(); ++k)
        table << (k ? ", " : "") << "[" << mbd::test::g17(static_cast<double>(k) * kPeriod) << ", " << mbd::test::g17(forces[k]) << "]";
    table << "]}";
    return table.str();
}

// The message of what `f` throws ("no error" when it throws nothing).
template <class F>
std::string message_of(F&& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return std::string(e.what());
    }
    return std::string("no error");
}

TEST(Simulator, LqrCartPoleThroughSetInputMatchesTheClosedLoop) {
    const Eigen::RowVector4d K = lqr_gain();
    const double t_end = 10.0;
    const mbd::Model model = scene(cart_pole_yaml("{type: input, name: force}"), "cart-pole.yaml");
    {
        mbd::Simulator sim(model, mbd::test::shared_registry(), quiet("dopri5", 1e-11, 0.0, t_end));
        ASSERT_EQ(sim.input_names(), std::vector<std::string>{"force"});
        EXPECT_NEAR(cart_pole_state(sim.state())[1], kTheta0, 1e-12);
    }
    const ClosedLoop loop = run_closed_loop(model, quiet("dopri5", 1e-11, 0.0, t_end));
    // the oracle: the same closed loop, RK4 at 1e-4 s on the equations above, to 5 s
    Vector4d oracle(0.0, kTheta0, 0.0, 0.0);
    const int substeps = 100;
    for (int k = 0; k < 500; ++k) {
        const double F = -(K * oracle)(0);
        const double h = kPeriod / substeps;
        for (int i = 0; i < substeps; ++i) {
            const Vector4d k1 = cart_pole_rate(oracle, F), k2 = cart_pole_rate(oracle + 0.5 * h * k1, F),
                           k3 = cart_pole_rate(oracle + 0.5 * h * k2, F), k4 = cart_pole_rate(oracle + h * k3, F);
            oracle += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        if (k + 1 == 50 || k + 1 == 100 || k + 1 == 200 || k + 1 == 500)
            EXPECT_NEAR(loop.theta[k], oracle[1], 1e-6) << "t = " << (k + 1) * kPeriod;
    }
    double worst_after_2s = 0.0;
    for (size_t k = 199; k < loop.theta.size(); ++k) worst_after_2s = std::max(worst_after_2s, std::abs(loop.theta[k]));
    EXPECT_LT(worst_after_2s, 1.0 * kPi / 180.0);
    EXPECT_GT(std::abs(loop.forces.front()), 0.1);  // the controller acted
}

// The recorded forces replayed as a `steps` time function through a whole simulate(): its
// steps end on the function's breakpoints and the right-hand side at a step's end takes the
// value of the step being integrated (integrator.hpp "breakpoints"), as the held input does,
// so the replay takes the closed loop's steps. Without the breakpoints (measured with them
// left out of simulate()) the replay was off by 7e-4 rad at 0.5 s with rk4 and 3e-8 with
// dopri5, growing as the open-loop unstable pole does (e^(3.97 t)). Output only every 0.5 s:
// the breakpoints alone end the steps.
void expect_replay_matches(const std::string& integrator, double tolerance, double step, double within) {
    const double t_end = 5.0;
    const mbd::Model model = scene(cart_pole_yaml("{type: input, name: force}"), "cart-pole.yaml");
    const ClosedLoop loop = run_closed_loop(model, quiet(integrator, tolerance, step, t_end));
    const mbd::Model replay = scene(cart_pole_yaml(steps_function(loop.forces)), "replay.yaml");
    mbd::SimulationSettings whole = quiet(integrator, tolerance, step, t_end);
    whole.output_step = 0.5;
    std::map<int, double> replayed;  // period index -> theta
    mbd::simulate(replay, mbd::test::shared_registry(), whole, [&](const mbd::SimulationSample& s) {
        replayed[static_cast<int>(std::lround(s.state.t / kPeriod))] = cart_pole_state(s.state)[1];
        return true;
    });
    for (int k : {50, 100, 200, 500}) {
        ASSERT_TRUE(replayed.count(k)) << k;
        EXPECT_NEAR(replayed[k], loop.theta[k - 1], within) << integrator << " t = " << k * kPeriod;
    }
}

TEST(Simulator, ReplayOfTheRecordedInputsThroughSimulateIsTheClosedLoop) {
    expect_replay_matches("rk4", 1e-6, 1e-3, 1e-10);  // (the tolerance is not used by rk4)
    expect_replay_matches("dopri5", 1e-10, 0.0, 1e-10);
    expect_replay_matches("dop853", 1e-10, 0.0, 1e-10);
}

// Two free bodies (no gravity) joined by a spring-damper between their mass centres.
std::string two_bodies_yaml(bool spring) {
    std::string y = "name: pair\ndimension: planar\ngravity: [0, 0]\nbodies:\n"
                    "  - {name: a, mass: 1.5, inertia: 0.2, position: [0, 0], velocity: [0.3, -0.2], angular_velocity: 1}\n"
                    "  - {name: b, mass: 0.7, inertia: 0.1, position: [1.2, 0.4], velocity: [-0.5, 0.6]}\n";
    if (spring) y += "forces:\n  - {name: s, type: spring_damper, bodies: [a, b], stiffness: 40, damping: 0.8, rest_length: 1}\n";
    return y;
}

TEST(Simulator, UserForceReproducesABuiltInSpringDamper) {
    const mbd::Model with_spring = scene(two_bodies_yaml(true), "spring.yaml");
    const mbd::Model without = scene(two_bodies_yaml(false), "free.yaml");
    for (const char* integrator : {"rk4", "dopri5"}) {
        const bool fixed = std::string(integrator) == "rk4";
        const mbd::SimulationSettings settings = quiet(integrator, 1e-10, fixed ? 1e-3 : 0.0, 2.0);
        mbd::Simulator builtin(with_spring, mbd::test::shared_registry(), settings);
        mbd::Simulator user(without, mbd::test::shared_registry(), settings);
        long calls = 0;
        user.set_user_force([&calls](const mbd::State& s) {
            ++calls;
            // f = k (l - l0) + c ldot along u (tension pulls a towards b), book Sec. 5.4
            const Eigen::Vector2d d = s.q.segment<2>(3) - s.q.segment<2>(0);
            const Eigen::Vector2d dv = s.v.segment<2>(3) - s.v.segment<2>(0);
            const double l = d.norm();
            const Eigen::Vector2d u = d / l;
            const double f = 40.0 * (l - 1.0) + 0.8 * u.dot(dv);
            VectorXd Q = VectorXd::Zero(6);
            Q.segment<2>(0) = f * u;
            Q.segment<2>(3) = -f * u;
            return Q;
        });
        builtin.advance_to(2.0);
        user.advance_to(2.0);
        EXPECT_GT(calls, 100);
        // the same steps (rk4): to round-off; dopri5's steps may differ where an error norm
        // lies at 1 within round-off, so there within the run's tolerance
        const double within = fixed ? 1e-12 : 1e-7;
        EXPECT_LT((builtin.state().q - user.state().q).cwiseAbs().maxCoeff(), within) << integrator;
        EXPECT_LT((builtin.state().v - user.state().v).cwiseAbs().maxCoeff(), within) << integrator;
        // the motion is not trivial: the spring acts
        EXPECT_GT((builtin.state().v - with_spring.initial_state().v).cwiseAbs().maxCoeff(), 0.1);
    }
}

// advance_to in 1000 pieces (at simulate()'s output times) against the whole run of
// simulate(). tolerance 0: bit for bit. cvode stops on every output time, so its whole run
// is compared with the pieces only; for the others one advance_to is the whole run.
void expect_pieces_match_whole_run(const mbd::Model& model, const mbd::SimulationSettings& settings, double tolerance) {
    mbd::SimulationSettings whole = settings;
    whole.output_step = settings.t_end / 1000.0;
    mbd::Simulator pieces(model, mbd::test::shared_registry(), settings);
    for (int k = 1; k <= 1000; ++k) pieces.advance_to(k == 1000 ? settings.t_end : k * whole.output_step);
    const mbd::SimulationResult result = mbd::simulate(model, mbd::test::shared_registry(), whole);
    if (settings.integrator != "cvode") {
        mbd::Simulator once(model, mbd::test::shared_registry(), settings);
        once.advance_to(settings.t_end);
        EXPECT_EQ(once.state().q, result.final_state.q) << settings.integrator;
        EXPECT_EQ(once.state().v, result.final_state.v) << settings.integrator;
        EXPECT_EQ(once.stats().steps, result.stats.steps) << settings.integrator;
    }
    if (tolerance == 0.0) {
        EXPECT_EQ(pieces.state().q, result.final_state.q) << settings.integrator;
        EXPECT_EQ(pieces.state().v, result.final_state.v) << settings.integrator;
    } else {
        EXPECT_LT((pieces.state().q - result.final_state.q).cwiseAbs().maxCoeff(), tolerance) << settings.integrator;
        EXPECT_LT((pieces.state().v - result.final_state.v).cwiseAbs().maxCoeff(), tolerance) << settings.integrator;
    }
    EXPECT_NEAR(pieces.time(), settings.t_end, 1e-15);
    // dopri5 and dop853 read the 999 times inside their steps from the continuous extension:
    // no step is cut, so the pieces take the whole run's steps (docs/embedding.md)
    if (settings.integrator == "dopri5" || settings.integrator == "dop853")
        EXPECT_EQ(pieces.stats().steps, result.stats.steps) << settings.integrator;
}

TEST(Simulator, AdvanceToInAThousandPiecesIsTheWholeRun) {
    const mbd::Model model = mbd::test::load("dynamics/pendulum-a01.yaml");
    expect_pieces_match_whole_run(model, quiet("rk4", 1e-6, 1e-3, 1.0), 0.0);
    expect_pieces_match_whole_run(model, quiet("dopri5", 1e-9, 0.0, 1.0), 1e-7);
    expect_pieces_match_whole_run(model, quiet("dop853", 1e-9, 0.0, 1.0), 1e-7);
    expect_pieces_match_whole_run(model, quiet("cvode", 1e-9, 0.0, 1.0), 1e-6);
}

// An input set while the state lags the integrator (a time read from the continuous
// extension): the run goes back to that time and continues with the new value. Oracle: the
// same inputs with the steps ending on every change (one call per input).
TEST(Simulator, AnInputSetAfterAnInterpolatedTimeActsFromThatTime) {
    const mbd::Model model = scene(cart_pole_yaml("{type: input, name: force}"), "cart-pole.yaml");
    mbd::Simulator read(model, mbd::test::shared_registry(), quiet("dopri5", 1e-10, 0.0, 1.0));
    mbd::Simulator direct(model, mbd::test::shared_registry(), quiet("dopri5", 1e-10, 0.0, 1.0));
    read.set_input("force", 2.0);
    read.advance_to(0.1);
    read.advance_to(0.15);  // no change since the last call: read from inside a step
    direct.set_input("force", 2.0);
    direct.advance_to(0.15);
    EXPECT_LT((read.state().q - direct.state().q).cwiseAbs().maxCoeff(), 1e-8);
    read.set_input("force", -5.0);
    direct.set_input("force", -5.0);
    read.advance_to(0.3);
    direct.advance_to(0.3);
    EXPECT_LT((read.state().q - direct.state().q).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LT((read.state().v - direct.state().v).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_NEAR(read.time(), 0.3, 1e-15);
}

TEST(Simulator, StepTakesOneIntegratorStepAndKeepsTheStepSize) {
    const mbd::Model model = mbd::test::load("dynamics/pendulum-a01.yaml");
    mbd::Simulator sim(model, mbd::test::shared_registry(), quiet("dopri5", 1e-8, 0.0, 1.0));
    double previous = sim.time();
    for (int k = 0; k < 20; ++k) {
        sim.step();
        EXPECT_GT(sim.time(), previous);
        previous = sim.time();
    }
    EXPECT_EQ(sim.stats().steps, 20);
    // the closed form of the A01 pendulum (tests/support), within the tolerance's reach
    EXPECT_LT((sim.state().q.head<2>() - mbd::test::a01_bob_position(sim.time())).norm(), 1e-6);
}

TEST(Simulator, EventsAreReportedAsTheyHappen) {
    const mbd::Model model = mbd::test::load("examples/force-joint-stop.yaml");
    const mbd::SimulationSettings settings = quiet("dopri5", 1e-9, 0.0, 3.0);
    mbd::Simulator sim(model, mbd::test::shared_registry(), settings);
    std::vector<std::pair<mbd::EventRecord, double>> told;  // the event and the time of the call it came in
    double call_start = 0.0;
    sim.on_event([&](const mbd::EventRecord& e) { told.emplace_back(e, call_start); });
    for (int k = 1; k <= 300; ++k) {
        call_start = sim.time();
        sim.advance_to(0.01 * k);
        for (const auto& [event, start] : told) {
            if (start != call_start) continue;
            EXPECT_GE(event.time, call_start);
            EXPECT_LE(event.time, sim.time());
        }
    }
    const mbd::SimulationResult whole = mbd::simulate(model, mbd::test::shared_registry(), settings);
    ASSERT_FALSE(whole.events.empty());
    ASSERT_EQ(told.size(), sim.events().size());
    ASSERT_FALSE(told.empty());
    EXPECT_EQ(told.front().first.force, "stop");
    EXPECT_EQ(told.front().first.kind, whole.events.front().kind);
    EXPECT_NEAR(told.front().first.time, whole.events.front().time, 1e-7);
}

// Bad input: each a clear error, and the Simulator usable after it.
TEST(Simulator, BadInputsAreClearErrors) {
    const mbd::Model model = scene(cart_pole_yaml("{type: input, name: force}"), "cart-pole.yaml");
    mbd::Simulator sim(model, mbd::test::shared_registry(), quiet("dopri5", 1e-8, 0.0, 1.0));
    // an input that does not exist: the known ones listed
    EXPECT_NE(message_of([&] { sim.set_input("forse", 1.0); }).find("its inputs are: force"), std::string::npos);
    EXPECT_NE(message_of([&] { sim.set_input("force", std::nan("")); }).find("finite"), std::string::npos);
    // a state of the wrong size, or with NaN
    EXPECT_NE(message_of([&] { sim.set_state(VectorXd::Zero(5), VectorXd::Zero(6)); }).find("needs 6 coordinates"),
              std::string::npos);
    VectorXd q = sim.state().q;
    q[1] = std::nan("");
    EXPECT_NE(message_of([&] { sim.set_state(q, sim.state().v); }).find("finite"), std::string::npos);
    EXPECT_NE(message_of([&] { sim.body_coordinates("poll"); }).find("its bodies are: cart, pole"), std::string::npos);
    EXPECT_NE(message_of([&] { sim.advance_to(-1.0); }).find("not before the current time"), std::string::npos);
    // a user force of the wrong shape, then one that throws: the step fails, the state stays
    // the last good one, stepping again is refused until reset()
    sim.advance_to(0.1);
    const mbd::State good = sim.state();
    sim.set_user_force([](const mbd::State&) { return VectorXd::Zero(4); });
    EXPECT_NE(message_of([&] { sim.step(); }).find("returned 4 values"), std::string::npos);
    EXPECT_EQ(sim.state().q, good.q);
    EXPECT_NE(message_of([&] { sim.step(); }).find("call reset()"), std::string::npos);
    sim.set_user_force({});
    sim.reset(good);
    sim.set_user_force([](const mbd::State&) -> VectorXd { throw std::runtime_error("controller offline"); });
    EXPECT_NE(message_of([&] { sim.advance_to(0.2); }).find("controller offline"), std::string::npos);
    EXPECT_NE(message_of([&] { sim.advance_to(0.2); }).find("call reset()"), std::string::npos);
    sim.set_user_force({});
    sim.reset(good);
    sim.advance_to(0.2);
    EXPECT_NEAR(sim.time(), 0.2, 1e-15);
    // a whole run of a scene with an input is refused, naming the input and its line
    const std::string refused = message_of([&] {
        mbd::simulate(model, mbd::test::shared_registry(), quiet("dopri5", 1e-8, 0.0, 1.0));
    });
    EXPECT_NE(refused.find("cart-pole.yaml:"), std::string::npos) << refused;
    EXPECT_NE(refused.find("the input 'force'"), std::string::npos) << refused;
}

TEST(Simulator, TwoSimulatorsOfOneModelHaveTheirOwnInputsAndStateWritesAreAssembled) {
    const mbd::Model model = scene(cart_pole_yaml("{type: input, name: force}"), "cart-pole.yaml");
    mbd::Simulator pushed(model, mbd::test::shared_registry(), quiet("dopri5", 1e-10, 0.0, 1.0));
    mbd::Simulator idle(model, mbd::test::shared_registry(), quiet("dopri5", 1e-10, 0.0, 1.0));
    pushed.set_input("force", 2.0);
    EXPECT_EQ(idle.input("force"), 0.0);
    pushed.advance_to(0.5);
    idle.advance_to(0.5);
    EXPECT_GT(pushed.body_coordinates("cart")[0], idle.body_coordinates("cart")[0] + 0.05);
    // a written cart position off the rail (y = 0.3) is assembled back onto it; the pole
    // follows its pin
    VectorXd q = idle.body_coordinates("cart");
    q[1] = 0.3;
    idle.set_body_state("cart", q, idle.body_velocities("cart"));
    EXPECT_NEAR(idle.body_coordinates("cart")[1], 0.0, 1e-8);
    EXPECT_NEAR(idle.time(), 0.5, 1e-15);
}

// A joint's coordinate and rate, read and written. Oracles: the bodies' own coordinates (the
// rail's displacement is the cart's x from the rail's point, the pin's angle the pole's body
// angle less the cart's, book Eq. 3.80) and the constraints (the pole's centre half its length from the pin, the cart on the rail).
TEST(Simulator, JointStateByNameIsReadAndWrittenOntoTheConstraints) {
    const mbd::Model model = scene(cart_pole_yaml("{type: input, name: force}"), "cart-pole.yaml");
    mbd::Simulator sim(model, mbd::test::shared_registry(), quiet("dopri5", 1e-10, 0.0, 1.0));
    sim.set_input("force", 2.0);
    sim.advance_to(0.3);
    const mbd::State& s = sim.state();
    EXPECT_NEAR(sim.joint_coordinate("rail"), s.q[0], 1e-12);
    EXPECT_NEAR(sim.joint_rate("rail"), s.v[0], 1e-12);
    EXPECT_NEAR(sim.joint_coordinate("pin"), s.q[5] - s.q[2], 1e-12);
    EXPECT_NEAR(sim.joint_rate("pin"), s.v[5] - s.v[2], 1e-12);

    const double pole_angle = 0.5 * kPi - 0.2;  // the cart does not turn on its rail: the pole's body angle
    sim.set_joint_state("pin", pole_angle, 0.7);
    EXPECT_NEAR(sim.time(), 0.3, 1e-15);
    EXPECT_NEAR(sim.joint_coordinate("pin"), pole_angle, 1e-10);
    EXPECT_NEAR(sim.joint_rate("pin"), 0.7, 1e-10);
    const VectorXd q = sim.state().q, v = sim.state().v;
    EXPECT_NEAR(q[5], pole_angle, 1e-10);
    EXPECT_NEAR(q[3], q[0] + 0.5 * kl * std::cos(pole_angle), 1e-10);
    EXPECT_NEAR(q[4], 0.5 * kl * std::sin(pole_angle), 1e-10);
    EXPECT_NEAR(q[1], 0.0, 1e-12);
    EXPECT_NEAR(v[3], v[0] - 0.5 * kl * std::sin(pole_angle) * 0.7, 1e-10);  // the pin's velocity constraint
    sim.set_joint_state("rail", 0.25, -0.1);
    EXPECT_NEAR(sim.body_coordinates("cart")[0], 0.25, 1e-10);
    EXPECT_NEAR(sim.body_velocities("cart")[0], -0.1, 1e-10);
    // the pole turns a little too (the least change of all coordinates), still on its pin
    const VectorXd q2 = sim.state().q, v2 = sim.state().v;
    EXPECT_NEAR(q2[3], q2[0] + 0.5 * kl * std::cos(q2[5]), 1e-10);
    EXPECT_NEAR(q2[4], 0.5 * kl * std::sin(q2[5]), 1e-10);
    EXPECT_NEAR(v2[3], v2[0] - 0.5 * kl * std::sin(q2[5]) * v2[5], 1e-10);
    sim.advance_to(0.4);  // and runs on from there
    EXPECT_NEAR(sim.time(), 0.4, 1e-15);

    EXPECT_NE(message_of([&] { sim.joint_coordinate("pinn"); }).find("its joints are: rail, pin"), std::string::npos);
    EXPECT_NE(message_of([&] { sim.set_joint_state("pin", std::nan(""), 0.0); }).find("finite"), std::string::npos);
}

}  // namespace

namespace {

// docs/embedding.md's example, verbatim between the markers (EmbeddingDocShowsThisTest).
// [embedding example]
double run_cart_pole(mbd::Registry& registry, const std::string& scene_yaml) {
    const mbd::Model model = mbd::load_scene_text(scene_yaml, "cart-pole.yaml", registry);
    mbd::SimulationSettings settings;
    settings.integrator = "dopri5";          // empty: the automatic choice, as `mbd simulate`
    settings.integration.tolerance = 1e-9;
    settings.t_end = 2.0;                     // the expected end: sets the largest step, not a limit
    settings.messages = mbd::MessageLog::silent();
    mbd::Simulator sim(model, registry, settings);
    sim.on_event([](const mbd::EventRecord& e) { std::printf("%s at t = %g\n", e.force.c_str(), e.time); });
    while (sim.time() < 2.0) {
        const mbd::State& s = sim.state();               // q, v in the model's order
        const double tilt = 0.5 * 3.141592653589793 - s.q[5];  // the pole's angle from upright
        sim.set_input("force", 25.0 * tilt + 6.0 * -s.v[5] + s.q[0] + 2.0 * s.v[0]);  // held for 10 ms
        sim.advance_to(sim.time() + 0.01);
    }
    return 0.5 * 3.141592653589793 - sim.body_coordinates("pole")[2];
}
// [embedding example]

TEST(Simulator, EmbeddingDocShowsThisTest) {
    // the PD law of the example keeps the pole up: from 5 degrees to within 1 degree by 2 s
    const double tilt = run_cart_pole(mbd::test::shared_registry(), cart_pole_yaml("{type: input, name: force}"));
    EXPECT_LT(std::abs(tilt), 1.0 * kPi / 180.0);
    const std::string doc = mbd::test::read_text(mbd::test::source_dir() / "docs" / "embedding.md");
    const std::string test = mbd::test::read_text(mbd::test::source_dir() / "tests" / "test_simulator.cpp");
    const std::string marker = "// [embedding example]\n";
    const size_t from = test.find(marker) + marker.size(), to = test.find(marker, from);
    ASSERT_NE(to, std::string::npos);
    EXPECT_NE(doc.find(test.substr(from, to - from)), std::string::npos)
        << "docs/embedding.md must show the example of tests/test_simulator.cpp verbatim";
}

}  // namespace

#include "../examples/cartpole/cartpole_env.hpp"

namespace {

// examples/cartpole: a linear state-feedback policy (the signs of the LQR law) balances the
// pole for the whole episode; pushing one way only lets it fall within a few dozen steps, as
// the same equations integrated by hand say (about 10 steps from these starts).
TEST(Simulator, CartPoleEnvironment) {
    cartpole::Environment env((mbd::test::source_dir() / "examples" / "cartpole" / "cartpole.yaml").string(),
                              mbd::test::shared_registry());
    for (unsigned seed : {1u, 2u, 3u}) {
        cartpole::Observation o = env.reset(seed);
        for (double value : o) EXPECT_LE(std::abs(value), 0.05 + 1e-12);
        int steps = 0;
        double total = 0.0;
        for (;;) {
            const double push = 25.0 * o[2] + 6.0 * o[3] + o[0] + 2.0 * o[1];
            const cartpole::StepResult r = env.step(push > 0.0 ? 1 : 0);
            ++steps;
            total += r.reward;
            o = r.observation;
            ASSERT_FALSE(r.terminated) << "seed " << seed << " step " << steps;
            if (r.truncated) break;
        }
        EXPECT_EQ(steps, 500);
        EXPECT_EQ(total, 500.0);
        env.reset(seed);
        int falling = 0;
        for (bool done = false; !done && falling < 500; ++falling) done = env.step(1).terminated;
        EXPECT_GT(falling, 3);
        EXPECT_LT(falling, 40) << "seed " << seed;
    }
}

}  // namespace
