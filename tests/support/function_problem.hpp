// Integrator tests on plain ODEs: an OdeProblem from a lambda (with an optional projection) and
// one run of a named integrator that records every output.
#pragma once

#include <mbd/integrator.hpp>

#include <Eigen/Core>

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

}  // namespace mbd::test
