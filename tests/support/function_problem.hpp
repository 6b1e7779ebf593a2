// Integrator tests on plain ODEs: an OdeProblem from a lambda (with an optional projection) and
// one run of a named integrator that records every output.
#pragma once

#include <mbd/integrator.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace mbd::test {

class FunctionProblem : public OdeProblem {
public:
    using Rhs = std::function<void(double, const Eigen::VectorXd&, Eigen::VectorXd&)>;
    using Project = std::function<bool(double, Eigen::VectorXd&)>;
    FunctionProblem(int n, Rhs f, Project p = {}) : n_(n), f_(std::move(f)), p_(std::move(p)) {}
    int size() const override { return n_; }
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override {
        ydot.resize(n_);
        f_(t, y, ydot);
        ++calls;
    }
    bool project(double t, Eigen::VectorXd& y) override { return p_ ? p_(t, y) : true; }
    long calls = 0;

private:
    int n_;
    Rhs f_;
    Project p_;
};

struct RunResult {
    std::vector<double> t;
    std::vector<Eigen::VectorXd> y;
    IntegratorStats stats;
};

// `name` with `settings` from (t0, y0) through `outputs`, every output recorded.
inline RunResult run(const std::string& name, const IntegratorSettings& settings, OdeProblem& problem, double t0,
                     Eigen::VectorXd y0, const std::vector<double>& outputs) {
    RunResult r;
    make_integrator(name, settings)
        ->integrate(
            problem, t0, y0, outputs,
            [&](double t, const Eigen::VectorXd& y) {
                r.t.push_back(t);
                r.y.push_back(y);
                return true;
            },
            r.stats);
    return r;
}

// x'' = -w^2 x, x(0) = 1, x'(0) = 0, w = 2: x = cos wt. The largest error at T = 5 of the
// fixed-step `integrator` with step h (an integrator's order from the ratio of two steps).
inline double oscillator_error(const std::string& integrator, double h) {
    const double w = 2.0, T = 5.0;
    FunctionProblem problem(2, [w](double, const Eigen::VectorXd& y, Eigen::VectorXd& f) {
        f[0] = y[1];
        f[1] = -w * w * y[0];
    });
    IntegratorSettings s;
    s.step = h;
    Eigen::VectorXd y0(2);
    y0 << 1.0, 0.0;
    const Eigen::VectorXd y = run(integrator, s, problem, 0.0, y0, {T}).y.back();
    return std::max(std::abs(y[0] - std::cos(w * T)), std::abs(y[1] + w * std::sin(w * T)));
}

}  // namespace mbd::test
