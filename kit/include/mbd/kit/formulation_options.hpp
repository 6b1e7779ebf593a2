// The options of a formulation, typed. The host reads them once from the scene's
// `formulation:` map (core formulation_setup.hpp), writes the command line's choices
// over them, and hands them to Formulation::bind(); a formulation never parses them from
// text. The keys a formulation plugin has of its own (the embedding's `path`) it reads
// from FormulationSpec::params.
//
// The shared keys come in groups; a formulation says which groups it honours
// (Formulation::options_used()), and a scene key of another group is refused by name.
#pragma once

#include <mbd/kit/message_log.hpp>
#include <mbd/kit/partition_settings.hpp>

#include <optional>
#include <string>

namespace mbd {

enum class Stabilization { None, Projection, Baumgarte };
enum class LinearAlgebra { Auto, Dense, Sparse };

// Auto linear algebra: dense up to this many velocity coordinates, sparse above. Measured
// with bench/bench_augmented (docs/benchmarks.md): the sparse path is as fast as the dense
// one at 30 coordinates and faster beyond.
inline constexpr int kDefaultSparseThreshold = 30;

// The Newton-Raphson that solves the dependent positions (partitioned formulations).
struct NewtonSettings {
    double tolerance = 1e-12;  // |C|, scaled by the size of the coordinates
    int iterations = 25;
};

// The groups of shared keys (a bit set).
enum OptionGroup : unsigned {
    kStabilizationOptions = 1u << 0,  // stabilization, alpha, beta, projection_tolerance
    kLinearAlgebraOptions = 1u << 1,  // linear_algebra, sparse_threshold
    kSingularityOptions = 1u << 2,    // singularity_tolerance
    kPartitionOptions = 1u << 3,      // pivot_threshold, reselect_ratio, rank_tolerance, log
    kNewtonOptions = 1u << 4,         // newton_tolerance, newton_iterations
};
using OptionGroups = unsigned;

struct FormulationOptions {
    // kLinearAlgebraOptions
    LinearAlgebra algebra = LinearAlgebra::Auto;
    int sparse_threshold = kDefaultSparseThreshold;
    // kStabilizationOptions
    Stabilization stabilization = Stabilization::Projection;
    double baumgarte_alpha = 10.0;  // Cddot + 2 alpha Cdot + beta^2 C = 0 (book Sec. 6.12)
    double baumgarte_beta = 10.0;
    double projection_tolerance = 1e-12;
    // kSingularityOptions: relative pivot tolerance of the rank test (singularity.hpp); 0: no check
    double singularity_tolerance = 1e-5;
    // kPartitionOptions
    PartitionSettings partition;
    std::optional<bool> log_choices;  // `log`: report paths and re-selections (unset: the formulation's default)
    // kNewtonOptions
    NewtonSettings newton;

    MessageLog log;  // where the formulation's messages to the user go (default std::clog)
};

}  // namespace mbd
