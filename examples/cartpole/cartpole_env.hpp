// A gymnasium-style cart-pole environment (CartPole-v1's rules) on mbd's stepping Simulator,
// using only the public API (mbd/scene.hpp, mbd/simulator.hpp): reset() and step(action)
// return the observation [x, x_dot, theta, theta_dot] (theta: the pole from upright, positive
// towards +x); an action pushes the cart with -10 N (0) or +10 N (1) for 20 ms; the reward is
// 1 per step; an episode terminates when |theta| > 12 degrees or |x| > 2.4 m and is truncated
// after 500 steps. tests/test_simulator.cpp (CartPoleEnvironment) runs it.
#pragma once

#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulator.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <string>

namespace cartpole {

using Observation = std::array<double, 4>;

struct StepResult {
    Observation observation;
    double reward = 0.0;
    bool terminated = false;  // the pole fell or the cart left the track
    bool truncated = false;   // the episode's 500 steps are done
};

class Environment {
public:
    // scene: examples/cartpole/cartpole.yaml (its cart force the input `force`).
    Environment(const std::string& scene, mbd::Registry& registry)
        : model_(mbd::load_scene(scene, registry)), sim_(model_, registry, settings()) {}

    Observation reset(unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> start(-0.05, 0.05);
        const double x = start(rng), xd = start(rng), th = start(rng), thd = start(rng);
        const double lc = 0.5;  // the pole's centre from its pin
        mbd::State s = sim_.state();
        s.t = 0.0;
        s.q << x, 0.0, 0.0, x + lc * std::sin(th), lc * std::cos(th), kHalfPi - th;
        s.v << xd, 0.0, 0.0, xd + lc * std::cos(th) * thd, -lc * std::sin(th) * thd, -thd;
        sim_.reset(s);
        steps_ = 0;
        return observe();
    }

    StepResult step(int action) {
        sim_.set_input("force", action == 1 ? kForce : -kForce);
        sim_.advance_to(sim_.time() + kPeriod);
        ++steps_;
        StepResult r;
        r.observation = observe();
        r.reward = 1.0;
        r.terminated = std::abs(r.observation[2]) > kThetaLimit || std::abs(r.observation[0]) > kXLimit;
        r.truncated = !r.terminated && steps_ >= kMaxSteps;
        return r;
    }

private:
    static constexpr double kHalfPi = 1.5707963267948966, kForce = 10.0, kPeriod = 0.02;
    static constexpr double kThetaLimit = 12.0 * 3.141592653589793 / 180.0, kXLimit = 2.4;
    static constexpr int kMaxSteps = 500;

    static mbd::SimulationSettings settings() {
        mbd::SimulationSettings s;
        s.integrator = "dopri5";
        s.integration.tolerance = 1e-8;
        s.t_end = kMaxSteps * kPeriod;
        s.messages = mbd::MessageLog::silent();
        return s;
    }
    Observation observe() const {
        const mbd::State& s = sim_.state();
        return {s.q[0], s.v[0], kHalfPi - s.q[5], -s.v[5]};
    }

    mbd::Model model_;
    mbd::Simulator sim_;
    int steps_ = 0;
};

}  // namespace cartpole
