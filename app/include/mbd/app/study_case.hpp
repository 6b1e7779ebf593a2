// One case of a study: the base scene with the case's parameter values, its analysis, and
// the metrics of its result table (docs/sweep.md). A case that fails (the values make the
// scene invalid, the assembly or the integration fails, the statics do not converge) is a
// result with its failure kind and message, never an exception; only a stop signal
// (Interrupted) leaves run_case.
#pragma once

#include <mbd/app/study.hpp>

#include <string>
#include <vector>

namespace mbd {

// The columns of a case's result table, by analysis:
//  simulate  every column of `mbd simulate` with --reactions --diagnostics (t, motion, the
//            joints' reactions, energies and constraint violations), one row per output time;
//  inverse   the columns of `mbd inverse --reactions` (t, actuator efforts, reactions);
//  statics   one row: the equilibrium motion columns, JOINT.coordinate of every joint that has
//            one, the reactions, DRIVER.effort, residual and iterations;
//  modes     one row: modeK.natural_frequency, modeK.damped_frequency, modeK.damping_ratio for
//            K = 1 .. (velocities of the model), modes in ascending natural frequency.
std::vector<std::string> case_columns(const Model& model, const StudyAnalysis& analysis);

struct CaseResult {
    bool ok = false;
    std::string failure;                 // kind (scene, assembly_failure, newton_divergence, statics, ...)
    std::string message;
    std::vector<double> metrics;         // Study::metrics order (empty when failed)
    double cpu_seconds = 0.0;            // CPU time of the thread that ran it
    std::vector<double> series;          // rows x Study::series, row-major (simulate, inverse)
    long series_rows = 0;
};

CaseResult run_case(const Study& study, Registry& registry, const std::vector<double>& values);

}  // namespace mbd
