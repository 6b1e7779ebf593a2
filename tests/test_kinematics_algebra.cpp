// The assembler's two linear-algebra paths (dense Eigen, sparse CHOLMOD) give
// the same kinematics, and Auto switches to sparse for large systems.
#include "support/test_support.hpp"

#include <mbd/kinematics.hpp>

#include <gtest/gtest.h>

#include <sstream>

namespace mbd {
namespace {

std::vector<State> run(const Model& model, LinearAlgebra algebra) {
    KinematicsOptions options;
    options.newton.algebra = algebra;
    std::vector<State> states;
    run_kinematics(model, 0.12, 0.004, [&](const State& s, const Eigen::VectorXd&) {
        states.push_back(s);
        return true;
    }, options);
    return states;
}

TEST(KinematicsAlgebra, DenseAndSparsePathsAgreeOnTheFourBar) {
    Model model = load_scene(test::scene_path("book/four-bar-table32.yaml"), test::shared_registry());
    const auto dense = run(model, LinearAlgebra::Dense);
    const auto sparse = run(model, LinearAlgebra::Sparse);
    ASSERT_EQ(dense.size(), sparse.size());
    ASSERT_EQ(dense.size(), 31u);
    double worst = 0;
    for (size_t k = 0; k < dense.size(); ++k) {
        worst = std::max(worst, (dense[k].q - sparse[k].q).lpNorm<Eigen::Infinity>());
        worst = std::max(worst, (dense[k].v - sparse[k].v).lpNorm<Eigen::Infinity>() / 50.0);
    }
    EXPECT_LT(worst, 1e-10);
}

// A driven planar chain of 40 links (120 coordinates, four times the sparse threshold of 30):
// Auto picks the sparse path, and its motion matches the dense one. (150 links cost 40 s under the
// sanitizers, nearly all of it in the dense path's 450 x 450 factorizations, and checked no more.)
std::string chain_scene(int links) {
    std::ostringstream s;
    s << "dimension: planar\nbodies:\n";
    for (int k = 0; k < links; ++k)
        s << "  - {name: link" << k << ", mass: 1, inertia: 0.1, position: [" << k + 0.5 << ", 0], angle: 0}\n";
    s << "joints:\n";
    for (int k = 0; k < links; ++k)
        s << "  - {name: j" << k << ", type: revolute, bodies: [" << (k == 0 ? std::string("ground") : "link" + std::to_string(k - 1))
          << ", link" << k << "], point: [" << k << ", 0]}\n";
    s << "drivers:\n";
    for (int k = 0; k < links; ++k)
        s << "  - {joint: j" << k << ", motion: {type: harmonic, amplitude: 0.01, frequency: " << 1 + 0.01 * k << "}}\n";
    return s.str();
}

TEST(KinematicsAlgebra, LargeChainUsesTheSparsePathAndMatchesDense) {
    Model model = load_scene_text(chain_scene(40), "chain.yaml", test::shared_registry());
    ASSERT_GT(model.nv(), kDefaultSparseThreshold);
    MinNormSolver probe(LinearAlgebra::Auto);
    ConstraintSystem system(model);
    ConstraintValues values;
    Data data(model);
    system.evaluate(model.initial_state(), data, values);
    ASSERT_TRUE(probe.factor(values.J));
    EXPECT_EQ(probe.used(), LinearAlgebra::Sparse);

    const auto dense = run(model, LinearAlgebra::Dense);
    const auto automatic = run(model, LinearAlgebra::Auto);
    ASSERT_EQ(dense.size(), automatic.size());
    double worst = 0;
    for (size_t k = 0; k < dense.size(); ++k)
        worst = std::max(worst, (dense[k].q - automatic[k].q).lpNorm<Eigen::Infinity>());
    EXPECT_LT(worst, 1e-10);
    // the prescribed motion: link 0's angle follows 0.01 sin(t)
    EXPECT_NEAR(automatic.back().q[2], 0.01 * std::sin(0.12), 1e-10);
}

}  // namespace
}  // namespace mbd
