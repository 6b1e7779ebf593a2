// Issue 12: one Model shared by 8 threads, each simulating with its own System (its own
// Data) and its own formulation instance, from a different initial state, gives results
// bit-identical to the same runs one after another. The runs mix all four formulations on
// a planar loop with a spring-damper and a spatial top. CI also runs this test in a
// ThreadSanitizer build (scripts/test-threads.sh), where a data race is a failure.
#include "support/test_support.hpp"

#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Run {
    std::string formulation;
    double speed_factor = 1.0;              // the scene's initial velocities times this
    std::vector<Eigen::VectorXd> samples;   // [q; v] at every output time
};

void simulate(const mbd::Model& model, Run& run) {
    mbd::SimulationSettings s;
    s.formulation = run.formulation;
    s.integrator = "dopri5";
    s.integration.tolerance = 1e-8;
    s.t_end = 0.2;
    s.output_step = 0.02;
    s.progress = false;
    s.messages = mbd::MessageLog::silent();
    mbd::State start = model.initial_state();
    start.v *= run.speed_factor;
    s.initial_state = start;
    run.samples.clear();
    mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        Eigen::VectorXd row(sample.state.q.size() + sample.state.v.size());
        row << sample.state.q, sample.state.v;
        run.samples.push_back(row);
        return true;
    });
}

bool bit_identical(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

void expect_threads_match_serial(const std::string& scene) {
    const mbd::Model model = mbd::test::load(scene);
    const std::vector<std::string> formulations = {"augmented", "embedding", "amalgamated", "hamiltonian"};
    std::vector<Run> serial(8), parallel(8);
    for (int k = 0; k < 8; ++k) {
        serial[k].formulation = parallel[k].formulation = formulations[k % 4];
        serial[k].speed_factor = parallel[k].speed_factor = 1.0 + 0.1 * k;
    }
    for (Run& run : serial) simulate(model, run);
    std::vector<std::thread> threads;
    std::vector<std::string> errors(8);
    for (int k = 0; k < 8; ++k)
        threads.emplace_back([&, k] {
            try {
                simulate(model, parallel[k]);
            } catch (const std::exception& e) {
                errors[k] = e.what();
            }
        });
    for (std::thread& t : threads) t.join();
    for (int k = 0; k < 8; ++k) {
        SCOPED_TRACE(scene + ", run " + std::to_string(k) + " (" + serial[k].formulation + ")");
        EXPECT_EQ(errors[k], "");
        ASSERT_EQ(parallel[k].samples.size(), serial[k].samples.size());
        ASSERT_EQ(serial[k].samples.size(), 11u);  // 0, 0.02, ..., 0.2
        for (size_t i = 0; i < serial[k].samples.size(); ++i)
            EXPECT_TRUE(bit_identical(parallel[k].samples[i], serial[k].samples[i])) << "sample " << i;
    }
    // runs of one formulation from different initial speeds end in different states, so the
    // comparison above is not between eight copies of one run
    for (int k = 4; k < 8; ++k) EXPECT_FALSE(bit_identical(serial[k].samples.back(), serial[k - 4].samples.back()));
}

}  // namespace

TEST(Threads, EightThreadsOnOneModelMatchSerialRunsBitForBit) {
    expect_threads_match_serial("dynamics/four-bar-spring-damper.yaml");
    expect_threads_match_serial("dynamics/heavy-top.yaml");
}
