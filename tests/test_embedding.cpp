// The embedding formulation (book Sec. 6.5, Eq. 6.95; coordinate partitioning Sec. 6.12;
// recursive tree path in joint coordinates), against independent oracles: the book's
// Ex. 2.12 hand elimination, the augmented formulation (Eq. 6.141) on a four-bar driven
// through its rocker's dead points, the joints' own constraint equations and the dense
// B^T M B path on a 20-link spatial chain, and the topology query of `mbd check`.
#include <mbd/model_system.hpp>
#include <mbd/kit/partition.hpp>
#include <mbd/reactions.hpp>
#include <mbd/kit/topology.hpp>
#include <mbd/simulation.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <set>
#include <sstream>
#include <unistd.h>
#include <string>

#include "support/four_bar_dead_points.hpp"
#include "support/test_support.hpp"

namespace {

using mbd::test::shared_registry;

mbd::Model load_text(const std::string& name, const std::string& yaml) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("mbd-test-embedding-" + std::to_string(::getpid()) + "-" + name + ".yaml");
    std::ofstream(path) << yaml;
    mbd::Model model = mbd::load_scene(path.string(), shared_registry());
    std::filesystem::remove(path);
    return model;
}

// A formulation from the registry with formulation keys given as text pairs.
std::shared_ptr<mbd::Formulation> make(const std::string& type, const std::vector<std::pair<std::string, std::string>>& keys,
                                       mbd::Param& node) {
    node = mbd::Param();
    node.kind = mbd::Param::Kind::Map;
    for (const auto& [k, v] : keys) {
        mbd::Param p;
        p.kind = mbd::Param::Kind::Scalar;
        p.text = v;
        node.fields[k] = p;
    }
    mbd::FormulationSpec spec{type, type, mbd::Params("formulation '" + type + "'", &node)};
    return shared_registry().create_formulation(spec, "test");
}

// Capture std::clog while alive.
struct ClogCapture {
    std::ostringstream text;
    std::streambuf* old;
    ClogCapture() : old(std::clog.rdbuf(text.rdbuf())) {}
    ~ClogCapture() { std::clog.rdbuf(old); }
    int count(const std::string& what) const {
        int n = 0;
        const std::string s = text.str();
        for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
        return n;
    }
};

// --- Book Ex. 2.12 (L1457-1488): rank 2, dependent {x1, x3}, independent {x2, x4, x5},
// one redundant equation, and the reduced form [x1; x3] = -[[1, 1, 4], [0, -1, -7/2]] [x2; x4; x5].
TEST(Embedding, BookExample212CoordinateSelection) {
    Eigen::MatrixXd A(3, 5);
    A << 1, 1, 0, 1, 4, 2, 2, 2, 0, 1, 3, 3, 2, 1, 5;
    const mbd::CoordinatePartition p = mbd::partition_coordinates(A);
    EXPECT_EQ(p.rank, 2);
    ASSERT_EQ(p.dependent.size(), 2u);
    EXPECT_EQ(std::set<int>(p.dependent.begin(), p.dependent.end()), (std::set<int>{0, 2}));
    EXPECT_EQ(p.independent, (std::vector<int>{1, 3, 4}));
    ASSERT_EQ(p.redundant.size(), 1u);
    // the reduced form, whichever two rows were kept
    const Eigen::MatrixXd Jd = A(p.rows, std::vector<int>{0, 2});
    const Eigen::MatrixXd Ji = A(p.rows, p.independent);
    Eigen::MatrixXd reduced = -Jd.partialPivLu().solve(Ji);
    Eigen::MatrixXd book(2, 3);
    book << -1, -1, -4, 0, 1, 3.5;
    EXPECT_LT((reduced - book).cwiseAbs().maxCoeff(), 1e-14);
    std::printf("Ex. 2.12: rank %d, dependent {x%d, x%d}, redundant row %d\n", p.rank, p.dependent[0] + 1,
                p.dependent[1] + 1, p.redundant[0] + 1);
    // strict complete pivoting picks the largest entry (5, column x5) first: same rank
    const mbd::CoordinatePartition full = mbd::partition_coordinates(A, 1.0);
    EXPECT_EQ(full.rank, 2);
    EXPECT_EQ(full.dependent.front(), 4);
}

// --- The crank-rocker four-bar through its dead points (support/four_bar_dead_points.hpp).
// Started with rocker.angle independent, the run must re-select and still follow the augmented
// formulation.
const std::string kFourBar =
    mbd::test::four_bar_dead_points("formulation: {type: embedding, independent: [rocker.angle]}");

struct Trace {
    std::vector<mbd::State> states;
    std::vector<Eigen::VectorXd> lambdas;
    mbd::SimulationResult result;
};

Trace simulate(const mbd::Model& model, const std::string& formulation, double tol, double t_end, double output_step) {
    mbd::SimulationSettings s;
    s.formulation = formulation;
    s.integrator = "dopri5";
    s.integration.tolerance = tol;
    s.t_end = t_end;
    s.output_step = output_step;
    s.reactions = true;
    s.progress = false;
    Trace r;
    r.result = mbd::simulate(model, shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        r.states.push_back(sample.state);
        if (sample.lambda) r.lambdas.push_back(*sample.lambda);
        return true;
    });
    return r;
}

TEST(Embedding, FourBarThroughRockerDeadPointsReselectsAndMatchesAugmented) {
    const mbd::Model model = load_text("four-bar", kFourBar);
    const double tol = 1e-10, t_end = 3.0;
    Trace emb;
    int switches = 0;
    {
        ClogCapture capture;
        emb = simulate(model, "embedding", tol, t_end, 0.01);
        switches = capture.count("independent coordinates now");
        std::printf("%s", capture.text.str().c_str());
    }
    const Trace aug = simulate(model, "augmented", tol, t_end, 0.01);
    ASSERT_EQ(emb.states.size(), aug.states.size());
    double worst_q = 0.0, worst_v = 0.0, worst_lambda = 0.0, worst_c = 0.0;
    mbd::ModelSystem system(model);
    for (size_t k = 0; k < emb.states.size(); ++k) {
        worst_q = std::max(worst_q, (emb.states[k].q - aug.states[k].q).lpNorm<Eigen::Infinity>());
        worst_v = std::max(worst_v, (emb.states[k].v - aug.states[k].v).lpNorm<Eigen::Infinity>());
        worst_lambda = std::max(worst_lambda, (emb.lambdas[k] - aug.lambdas[k]).lpNorm<Eigen::Infinity>() /
                                                  std::max(1.0, aug.lambdas[k].lpNorm<Eigen::Infinity>()));
        mbd::ConstraintValues cv;
        system.constraints(emb.states[k], cv, true);
        worst_c = std::max(worst_c, cv.C.lpNorm<Eigen::Infinity>());
    }
    const double crank_turns = std::abs(emb.states.back().q[2] - emb.states.front().q[2]) / (2 * M_PI);
    std::printf("four-bar dead points: %d re-selections, crank turned %.2f times; vs augmented max |dq| %.3e, "
                "|dv| %.3e, relative |dlambda| %.3e; max |C| %.3e\n",
                switches, crank_turns, worst_q, worst_v, worst_lambda, worst_c);
    EXPECT_GE(switches, 1);
    EXPECT_GT(crank_turns, 1.0);  // the rocker passed both dead points at least once
    EXPECT_LT(worst_q, 1e-6);
    EXPECT_LT(worst_v, 1e-5);
    EXPECT_LT(worst_lambda, 1e-5);
    EXPECT_LT(worst_c, 1e-10);
}

TEST(Embedding, UnknownIndependentComponentIsAnInputError) {
    std::string yaml = kFourBar;
    yaml.replace(yaml.find("rocker.angle"), 12, "rocker.twist");
    const mbd::Model model = load_text("four-bar-bad", yaml);
    EXPECT_THROW(simulate(model, "embedding", 1e-8, 0.01, 0.01), mbd::InputError);
}

// --- a 20-link spatial chain with mixed joints, some listed child-first
std::string spatial_chain(int n) {
    const char* types[] = {"revolute", "spherical", "universal", "prismatic", "cylindrical", "screw"};
    std::ostringstream y;
    y << "name: chain\ndimension: spatial\ngravity: [0, 0, -9.81]\nbodies:\n";
    const double L = 0.5;
    for (int k = 0; k < n; ++k)
        y << "  - {name: link" << k << ", mass: " << 1.0 + 0.1 * k << ", inertia: [0.01, 0.02, 0.025], position: ["
          << (k + 0.5) * L << ", 0, 0]}\n";
    y << "joints:\n";
    for (int k = 0; k < n; ++k) {
        const std::string type = types[k % 6];
        const std::string parent = k == 0 ? "ground" : "link" + std::to_string(k - 1);
        const std::string child = "link" + std::to_string(k);
        const bool reversed = k > 0 && k % 4 == 3;
        y << "  - {name: j" << k << ", type: " << type << ", bodies: [" << (reversed ? child : parent) << ", "
          << (reversed ? parent : child) << "], point: [" << k * L << ", 0, 0]";
        if (type == "revolute") y << ", axis: [0, " << (k % 2 ? 1 : 0) << ", " << (k % 2 ? 0 : 1) << "]";
        if (type == "universal") y << ", axes: [[0, 0, 1], [0, 1, 0]]";
        if (type == "prismatic" || type == "cylindrical") y << ", axis: [1, 0.3, 0.2]";
        if (type == "screw") y << ", axis: [1, 0, 0], pitch: 0.05";
        y << "}\n";
    }
    return y.str();
}

std::string planar_chain(int n) {
    std::ostringstream y;
    y << "name: planar-chain\ndimension: planar\ngravity: [0, -9.81]\nbodies:\n";
    for (int k = 0; k < n; ++k)
        y << "  - {name: link" << k << ", mass: 1, inertia: 0.02, position: [" << (k + 0.5) * 0.5 << ", 0]}\n";
    y << "joints:\n";
    for (int k = 0; k < n; ++k) {
        const std::string parent = k == 0 ? "ground" : "link" + std::to_string(k - 1);
        const std::string child = "link" + std::to_string(k);
        const bool reversed = k % 3 == 2;
        y << "  - {name: j" << k << ", type: " << (k % 4 == 1 ? "prismatic" : "revolute") << ", bodies: ["
          << (reversed ? child : parent) << ", " << (reversed ? parent : child) << "], point: [" << k * 0.5 << ", 0]"
          << (k % 4 == 1 ? ", axis: [1, 0.5]" : "") << "}\n";
    }
    return y.str();
}

void compare_tree_and_dense(const mbd::Model& model, double* out_acc, double* out_lambda) {
    mbd::ModelSystem system(model);
    std::string reason;
    ASSERT_TRUE(mbd::recursive_embedding_possible(system, &reason)) << reason;
    mbd::Param n1, n2, n3;
    auto tree = make("embedding", {{"path", "recursive"}}, n1);
    auto dense = make("embedding", {{"path", "dense"}}, n2);
    auto aug = make("augmented", {}, n3);
    mbd::FormulationOptions quiet;
    quiet.log_choices = false;
    tree->bind(system, quiet);
    dense->bind(system, quiet);
    aug->bind(system, quiet);
    mbd::State s0 = system.initial_state();
    system.assemble(s0, true);
    system.consistent_velocities(s0, true);
    Eigen::VectorXd y;
    tree->to_ode(s0, y);
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    double worst_acc = 0.0, worst_lambda = 0.0, worst_c = 0.0, worst_aug = 0.0;
    for (int trial = 0; trial < 5; ++trial) {
        Eigen::VectorXd yr = y;
        for (int k = 0; k < yr.size(); ++k) yr[k] += 0.6 * uni(rng);
        tree->project(0.0, yr);
        mbd::State s;
        tree->from_ode(0.0, yr, s);
        // the forward kinematics satisfies the joints' own constraint equations
        mbd::ConstraintValues cv;
        system.constraints(s, cv, true);
        worst_c = std::max(worst_c, cv.C.lpNorm<Eigen::Infinity>());
        worst_c = std::max(worst_c, (cv.J * s.v + cv.C_t).lpNorm<Eigen::Infinity>());
        // and to_ode inverts from_ode
        Eigen::VectorXd back;
        tree->to_ode(s, back);
        mbd::State s2;
        tree->from_ode(0.0, back, s2);
        EXPECT_LT((s2.q - s.q).lpNorm<Eigen::Infinity>(), 1e-12);
        EXPECT_LT((s2.v - s.v).lpNorm<Eigen::Infinity>(), 1e-11);
        Eigen::VectorXd a_tree, a_dense, a_aug, l_tree, l_dense;
        tree->accelerations(s, a_tree);
        dense->accelerations(s, a_dense);
        aug->accelerations(s, a_aug);
        tree->multipliers(s, l_tree);
        dense->multipliers(s, l_dense);
        const double scale = std::max(1.0, a_dense.lpNorm<Eigen::Infinity>());
        worst_acc = std::max(worst_acc, (a_tree - a_dense).lpNorm<Eigen::Infinity>() / scale);
        worst_aug = std::max(worst_aug, (a_tree - a_aug).lpNorm<Eigen::Infinity>() / scale);
        worst_lambda = std::max(worst_lambda, (l_tree - l_dense).lpNorm<Eigen::Infinity>() /
                                                  std::max(1.0, l_dense.lpNorm<Eigen::Infinity>()));
    }
    std::printf("%s: tree vs dense relative |dvdot| %.3e (vs augmented %.3e), |dlambda| %.3e; kinematics |C|, |Cdot| %.3e\n",
                model.name.c_str(), worst_acc, worst_aug, worst_lambda, worst_c);
    EXPECT_LT(worst_c, 1e-12);
    EXPECT_LT(worst_acc, 1e-10);
    EXPECT_LT(worst_aug, 1e-8);
    EXPECT_LT(worst_lambda, 1e-8);
    if (out_acc) *out_acc = worst_acc;
    if (out_lambda) *out_lambda = worst_lambda;
}

TEST(Embedding, RecursiveMatchesDenseOnA20LinkSpatialChainWithMixedJoints) {
    compare_tree_and_dense(load_text("chain", spatial_chain(20)), nullptr, nullptr);
}

TEST(Embedding, RecursiveMatchesDenseOnAPlanarChain) {
    compare_tree_and_dense(load_text("planar-chain", planar_chain(12)), nullptr, nullptr);
}

// The recursive path's rhs runs planar trees in planar algebra (planar_articulated_body.hpp);
// its accelerations and reactions at a State stay on the spatial algorithm. The oracle of
// the rhs is the augmented formulation: at random joint-coordinate states, the body
// accelerations that ydot = rhs(y) implies, the central difference
// (v(y + h ydot) - v(y - h ydot)) / 2h of the forward kinematics, must be augmented's vdot.
// Every planar tree scene under scenes/ (pins, sliders, reversed edges, marker angles, free
// bodies, forces of every kind) plus a 12-link chain of pins and oblique sliders.
TEST(Embedding, PlanarTreesRhsInPlanarAlgebraGivesAugmentedAccelerations) {
    std::vector<std::pair<std::string, mbd::Model>> models;
    models.emplace_back("planar-chain", load_text("planar-chain", planar_chain(12)));
    // a slider, a reversed pin and a reversed slider driven (prescribed motion, f'' != 0)
    models.emplace_back("planar-chain-driven",
                        load_text("planar-chain-driven",
                                  planar_chain(12) +
                                      "drivers:\n"
                                      "  - {name: d1, joint: j1, motion: {type: polynomial, coefficients: [0, 0.3, 0.8]}}\n"
                                      "  - {name: d2, joint: j2, motion: {type: polynomial, coefficients: [0, -0.5, 1.2]}}\n"
                                      "  - {name: d5, joint: j5, motion: {type: polynomial, coefficients: [0, 0.2, -0.6]}}\n"));
    for (const char* dir : {"bench", "book", "dynamics", "examples", "extreme", "statics", "reference"})
        for (const auto& entry : std::filesystem::directory_iterator(mbd::test::scene_path(dir))) {
            if (entry.path().extension() != ".yaml") continue;
            try {
                mbd::Model model = mbd::load_scene(entry.path().string(), shared_registry());
                if (model.dimension == mbd::Dimension::Planar) models.emplace_back(entry.path().filename().string(), model);
            } catch (const mbd::InputError&) {  // the scenes of bad-input tests
            }
        }
    int checked = 0, with_slider = 0, with_free_body = 0, with_driver = 0;
    for (const auto& [name, model] : models) {
        mbd::ModelSystem system(model);
        if (!mbd::recursive_embedding_possible(system) || system.nv() > 300) continue;
        mbd::Param n1, n2;
        auto tree = make("embedding", {{"path", "recursive"}}, n1);
        auto aug = make("augmented", {}, n2);
        std::string log;
        mbd::FormulationOptions options;
        options.log = mbd::MessageLog([&](const std::string& line) { log += line + "\n"; });
        mbd::FormulationOptions quiet;
        quiet.log_choices = false;
        try {
            aug->bind(system, quiet);
        } catch (const mbd::InputError&) {  // extreme/zero-mass-body: refused by design
            continue;
        }
        tree->bind(system, options);
        EXPECT_NE(log.find("planar algebra"), std::string::npos) << name << ": " << log;
        mbd::State s0 = system.initial_state();
        system.assemble(s0, true);
        system.consistent_velocities(s0, true);
        Eigen::VectorXd y, ydot;
        tree->to_ode(s0, y);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> uni(-1.0, 1.0);
        double worst = 0.0;
        for (int trial = 0; trial < 3; ++trial) {
            Eigen::VectorXd yr = y;
            for (int k = 0; k < yr.size(); ++k) yr[k] += 0.3 * uni(rng);
            mbd::State s, plus, minus;
            tree->from_ode(0.0, yr, s);
            tree->rhs(0.0, yr, ydot);
            // a difference in time: a driven joint's speed follows its driver's f'(t)
            const double h = 1e-6 / std::max(1.0, ydot.lpNorm<Eigen::Infinity>());
            tree->from_ode(h, yr + h * ydot, plus);
            tree->from_ode(-h, yr - h * ydot, minus);
            const Eigen::VectorXd vdot_tree = (plus.v - minus.v) / (2.0 * h);
            Eigen::VectorXd vdot_aug;
            aug->accelerations(s, vdot_aug);
            worst = std::max(worst, (vdot_tree - vdot_aug).lpNorm<Eigen::Infinity>() /
                                        std::max(1.0, vdot_aug.lpNorm<Eigen::Infinity>()));
        }
        std::printf("%-40s nv %4d: rhs vs augmented, relative |dvdot| %.2e\n", name.c_str(), system.nv(), worst);
        EXPECT_LT(worst, 1e-6) << name;
        ++checked;
        std::vector<char> jointed(model.bodies.size(), 0);
        bool slider = false;
        for (const mbd::JointInstance& j : model.joints) {
            slider = slider || j.type == "prismatic";
            for (int b : j.bodies)
                if (b >= 0) jointed[b] = 1;
        }
        with_slider += slider;
        with_free_body += std::count(jointed.begin(), jointed.end(), 0) > 0;
        with_driver += !model.drivers.empty();
    }
    std::printf("%d planar trees, %d with a slider, %d with a free body, %d driven\n", checked, with_slider,
                with_free_body, with_driver);
    EXPECT_GE(checked, 10);
    EXPECT_GE(with_slider, 2);
    EXPECT_GE(with_free_body, 1);
    EXPECT_GE(with_driver, 1);
}

TEST(Embedding, TopologyDecidesThePath) {
    const mbd::Model chain = load_text("chain-topology", spatial_chain(6));
    mbd::ModelSystem tree(chain);
    EXPECT_TRUE(mbd::analyse_topology(tree).tree);
    EXPECT_TRUE(mbd::recursive_embedding_possible(tree));
    const mbd::Model four_bar = load_text("four-bar-topology", kFourBar);
    mbd::ModelSystem loop(four_bar);
    const mbd::Topology t = mbd::analyse_topology(loop);
    EXPECT_FALSE(t.tree);
    ASSERT_EQ(t.cut_joints.size(), 1u);
    EXPECT_EQ(loop.joint(t.cut_joints[0]).name, "C");
    std::string reason;
    EXPECT_FALSE(mbd::recursive_embedding_possible(loop, &reason));
    EXPECT_NE(reason.find("cut joint 'C'"), std::string::npos) << reason;
    // `mbd check` prints the decision
    const auto out = mbd::test::run_mbd("check " + mbd::test::scene_path("dynamics/heavy-top.yaml").string());
    EXPECT_NE(out.out.find("embedding: recursive path"), std::string::npos) << out.out;
    const auto out2 = mbd::test::run_mbd("check " + mbd::test::scene_path("dynamics/four-bar-spring-damper.yaml").string());
    EXPECT_NE(out2.out.find("embedding: closure path"), std::string::npos) << out2.out;
}

// A tree scene run through the simulation layer on the recursive path follows the augmented formulation.
TEST(Embedding, RecursivePathSimulationMatchesAugmented) {
    const mbd::Model model = load_text("chain-sim", spatial_chain(8));
    const double tol = 1e-10;
    Trace emb;
    {
        ClogCapture capture;
        emb = simulate(model, "embedding", tol, 0.5, 0.05);
        EXPECT_EQ(capture.count("embedding: recursive path"), 1) << capture.text.str();
    }
    const Trace aug = simulate(model, "augmented", tol, 0.5, 0.05);
    ASSERT_EQ(emb.states.size(), aug.states.size());
    double worst = 0.0;
    for (size_t k = 0; k < emb.states.size(); ++k)
        worst = std::max(worst, (emb.states[k].q - aug.states[k].q).lpNorm<Eigen::Infinity>());
    std::printf("8-link spatial chain, recursive embedding vs augmented over 0.5 s: max |dq| %.3e\n", worst);
    EXPECT_LT(worst, 1e-6);
}

}  // namespace

namespace {

using mbd::test::position_difference;

// Redundant constraints: the orthogonal Bricard linkage (30 joint rows, rank 29) under
// gravity. The dense path drops the dependent row, names it, and moves as the augmented
// formulation does (whose least-squares multipliers handle the redundancy).
TEST(Embedding, BricardRedundantRowIsDroppedAndNamed) {
    const mbd::Model model = mbd::load_scene(mbd::test::scene_path("book/bricard.yaml").string(), shared_registry());
    Trace emb;
    std::string log;
    {
        ClogCapture capture;
        emb = simulate(model, "embedding", 1e-10, 0.5, 0.05);
        log = capture.text.str();
    }
    const Trace aug = simulate(model, "augmented", 1e-10, 0.5, 0.05);
    std::printf("%s", log.c_str());
    EXPECT_NE(log.find("1 redundant constraint row dropped: joint '"), std::string::npos) << log;
    const double dq = position_difference(model, emb.states.back().q, aug.states.back().q);
    const double moved = position_difference(model, emb.states.back().q, emb.states.front().q);
    std::printf("Bricard, 0.5 s: embedding vs augmented |dq| %.3e (moved %.3g)\n", dq, moved);
    EXPECT_GT(moved, 1e-2);
    EXPECT_LT(dq, 1e-7);
}

// Every example scene (one per joint and force type: gears and racks take the dense
// path, the others the recursive one) follows the augmented formulation.
TEST(Embedding, ExampleScenesMatchAugmented) {
    for (const auto& entry : std::filesystem::directory_iterator(mbd::test::scene_path("examples"))) {
        if (entry.path().extension() != ".yaml") continue;
        const mbd::Model model = mbd::load_scene(entry.path().string(), shared_registry());
        Trace emb;
        std::string path;
        {
            ClogCapture capture;
            emb = simulate(model, "embedding", 1e-10, 0.3, 0.3);
            path = capture.text.str().substr(0, capture.text.str().find('('));
        }
        const Trace aug = simulate(model, "augmented", 1e-10, 0.3, 0.3);
        const double dq = position_difference(model, emb.states.back().q, aug.states.back().q);
        std::printf("%-48s %-28s |dq| %.3e\n", entry.path().filename().c_str(), path.c_str(), dq);
        EXPECT_LT(dq, 1e-7) << entry.path();
    }
}

}  // namespace
