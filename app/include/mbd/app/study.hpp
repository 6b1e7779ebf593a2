// A parameter study (`mbd sweep`, docs/sweep.md): the study file read and checked against its
// base scene before any case runs. A study names a base scene, the scalar scene keys it varies
// (paths of scene_parameters.hpp), the design that chooses their values, the analysis each case
// runs, and the metrics kept of each case's result table.
#pragma once

#include <mbd/app/scene_loader.hpp>
#include <mbd/model.hpp>
#include <mbd/registry.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/simulation.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mbd {

// How a design draws a parameter. A grid takes `values` (or `range` with `count` points); a
// Latin hypercube or Monte Carlo design maps a probability u in (0, 1) through the inverse CDF
// of the named distribution (study_distribution.cpp).
struct StudyParameter {
    std::string path;                  // scene key (bodies.bob.mass, joints.O.point[0])
    std::string where;                 // study file:line
    std::vector<double> values;        // grid points (from `values`, or `range` + `count`)
    std::string distribution;          // uniform | normal | lognormal | triangular ("" for a grid of values)
    double a = 0.0, b = 0.0, c = 0.0;  // uniform [a, b]; normal mean a, sd b; lognormal mu a, sigma b;
                                       // triangular lower a, mode b, upper c
};

enum class DesignType { Grid, LatinHypercube, MonteCarlo };

struct StudyDesign {
    DesignType type = DesignType::Grid;
    long cases = 0;                    // LHS and Monte Carlo (a grid: the product of the value counts)
    unsigned long long seed = 1;
};

enum class AnalysisType { Simulate, Statics, Inverse, Modes };

// A simulate analysis's run before the study's keys are read: dopri5 at its default tolerance.
inline SimulationSettings simulate_defaults() {
    SimulationSettings s;
    s.integrator = "dopri5";
    return s;
}

struct StudyAnalysis {
    AnalysisType type = AnalysisType::Simulate;
    // simulate: the run (its integrator "dopri5" unless the study names one); inverse: run.t_end
    // and the output step, run.integration.step (required there)
    SimulationSettings run = simulate_defaults();
    // statics (and modes about the statics)
    double time = 0.0, statics_tolerance = 1e-10;
    int max_iterations = 500;
    std::string objective = "auto", solver = "ipopt";
    // modes: the reference, statics or initial
    std::string about = "statics";
};

enum class Reduction { Final, Max, Min, Rms };

// One kept number per case: a reduction of a column of the case's result table.
struct StudyMetric {
    Reduction reduction = Reduction::Final;
    std::string column;
    std::string name;                  // the table column: "max(bob.vy)"
    std::string where;
};

struct Study {
    std::filesystem::path file;
    std::string text;                  // the study file as written (kept in the results)
    std::filesystem::path scene;       // the base scene (relative to the study file)
    std::shared_ptr<const Model> model;
    StudyAnalysis analysis;
    std::vector<StudyParameter> parameters;
    StudyDesign design;
    std::vector<StudyMetric> metrics;
    std::vector<std::string> series;   // columns kept per case as a time series (simulate, inverse)
    std::vector<std::string> columns;  // every column of a case's result table
};

// The name of a reduction, as in the study file and the metric names.
std::string reduction_name(Reduction r);
std::string analysis_name(AnalysisType a);

// Reads and checks the study (keys, the base scene, every parameter path against it, every
// metric and series column against the analysis's columns); InputError naming the study
// file:line and the key, with near matches for a mistyped parameter path or column. The base
// scene is read by `load` (a model file too when the command line gives the import's loader).
Study read_study(const std::filesystem::path& file, Registry& registry, const SceneLoader& load = {});

}  // namespace mbd
