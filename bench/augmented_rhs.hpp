// The median CPU time of one rhs of the augmented formulation bound to a system at a state, with
// the options `mbd simulate` gives it (shared by the collision and flexible benchmarks).
#pragma once

#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>

#include "bench_stats.hpp"

inline double augmented_rhs_seconds(mbd::Registry& registry, mbd::ModelSystem& system, const mbd::State& state) {
    mbd::Param node;
    node.kind = mbd::Param::Kind::Map;
    mbd::FormulationSpec spec{"augmented", "augmented", mbd::Params("formulation 'augmented'", &node)};
    auto f = registry.create_formulation(spec, "bench");
    mbd::FormulationOptions options;
    options.sparse_threshold = 30;  // as mbd simulate
    f->bind(system, options);
    Eigen::VectorXd y, ydot;
    f->to_ode(state, y);
    return median_seconds_per_call([&] { f->rhs(0.0, y, ydot); }, thread_cpu_clock());
}
