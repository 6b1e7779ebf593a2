// Issue 12: after a warm-up, a right-hand side and an accepted step allocate nothing, for
// every formulation on every scene of scenes/dynamics and scenes/bench. The formulation is
// bound and driven exactly as the simulation driver does it (bind, assemble, to_ode,
// project, rhs); the integrators rk4 and dopri5 then run over two horizons and must make the
// same number of allocations for both (the extra steps allocate nothing).
#include "support/allocation_counter.hpp"
#include "support/test_support.hpp"

#include <mbd/integrator.hpp>
#include <mbd/model_system.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using mbd::test::AllocationCount;

std::vector<std::string> allocation_scenes() {
    std::vector<std::string> scenes;
    for (const char* folder : {"dynamics", "bench"})
        for (const auto& entry : std::filesystem::directory_iterator(mbd::test::scene_path(folder)))
            if (entry.path().extension() == ".yaml") scenes.push_back(std::string(folder) + "/" + entry.path().filename().string());
    std::sort(scenes.begin(), scenes.end());
    return scenes;
}

class BoundProblem final : public mbd::OdeProblem {
public:
    explicit BoundProblem(mbd::Formulation& f) : f_(f) {}
    int size() const override { return f_.ode_size(); }
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override { f_.rhs(t, y, ydot); }
    bool project(double t, Eigen::VectorXd& y) override { return f_.project(t, y); }

private:
    mbd::Formulation& f_;
};

struct Counts {
    long rhs = 0;
    long steps[2] = {0, 0};
};

}  // namespace

TEST(Allocations, NoneAfterWarmUpPerRhsAndPerStep) {
    const std::vector<std::string> formulations = {"augmented", "embedding", "amalgamated", "hamiltonian"};
    int pairs = 0;
    for (const std::string& path : allocation_scenes()) {
        const mbd::Model model = mbd::test::load(path);
        for (const std::string& type : formulations) {
            mbd::Param node;
            auto formulation = mbd::test::make_formulation(type, node);
            mbd::ModelSystem system(model);
            mbd::FormulationOptions options;
            options.log = mbd::MessageLog::silent();
            options.sparse_threshold = 30;
            formulation->bind(system, options);
            mbd::State state = system.initial_state();
            state.t = 0.0;
            system.assemble(state, true);
            system.consistent_velocities(state, true);
            Eigen::VectorXd y, ydot(formulation->ode_size());
            formulation->to_ode(state, y);
            ASSERT_TRUE(formulation->project(0.0, y)) << path << " " << type;
            for (int k = 0; k < 3; ++k) formulation->rhs(0.0, y, ydot);
            Counts c;
            {
                AllocationCount count;
                for (int k = 0; k < 10; ++k) formulation->rhs(1e-3 * k, y, ydot);
                c.rhs = count.stop();
            }
            EXPECT_EQ(c.rhs, 0) << path << " with " << type << ": " << c.rhs << " allocations in 10 rhs";
            for (const char* integrator_name : {"rk4", "dopri5"}) {
                long counts[2] = {0, 0};
                long steps[2] = {0, 0};
                for (int run = 0; run < 2; ++run) {
                    // rk4: 5 and 10 steps of 1 ms; dopri5 at 1e-6 over 50 and 100 ms
                    const bool rk4 = std::string(integrator_name) == "rk4";
                    const double T = (rk4 ? 0.005 : 0.05) * (run + 1);
                    mbd::IntegratorSettings s;
                    s.step = rk4 ? 1e-3 : 0.0;
                    s.tolerance = 1e-6;
                    auto integrator = mbd::make_integrator(integrator_name, s);
                    Eigen::VectorXd y_run = y;
                    BoundProblem problem(*formulation);
                    mbd::IntegratorStats stats;
                    const std::vector<double> outputs = {T};
                    const mbd::OutputCallback output = [](double, const Eigen::VectorXd&) { return true; };
                    AllocationCount count;
                    integrator->integrate(problem, 0.0, y_run, outputs, output, stats);
                    counts[run] = count.stop();
                    steps[run] = stats.steps;
                }
                EXPECT_GT(steps[1], steps[0]) << path << " " << type << " " << integrator_name;
                EXPECT_EQ(counts[0], counts[1]) << path << " with " << type << " + " << integrator_name << ": "
                                                << counts[0] << " allocations in " << steps[0] << " steps, "
                                                << counts[1] << " in " << steps[1];
            }
            std::printf("%-28s %-12s rhs allocations %ld\n", path.c_str(), type.c_str(), c.rhs);
            ++pairs;
        }
    }
    std::printf("%d scene x formulation pairs covered\n", pairs);
    EXPECT_GT(pairs, 60);
}
