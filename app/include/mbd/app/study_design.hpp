// The cases of a study's design (docs/sweep.md, "Designs"): a full grid, a Latin hypercube or
// Monte Carlo samples. Every design is a pure function of the study file (its seed included):
// each rank of an MPI run computes the same cases, and a resumed run the same ones again.
#pragma once

#include <mbd/app/study.hpp>

#include <vector>

namespace mbd {

// Row k holds the parameter values of case k, in the order of Study::parameters.
//  - grid: every combination of the value lists, the last parameter varying fastest;
//  - latin_hypercube: per parameter, the `cases` equal-probability strata in a random order
//    and a random point in each (McKay, Beckman and Conover 1979), through the inverse CDF;
//  - monte_carlo: independent probabilities through the inverse CDF.
// The random numbers are std::mt19937_64 from the seed (a sequence the C++ standard fixes),
// turned into probabilities and permutations here, not by the library's distributions
// (whose results the standard leaves to each implementation).
std::vector<std::vector<double>> design_cases(const Study& study);

// The value of probability u in (0, 1) under the parameter's distribution (inverse CDF).
double inverse_cdf(const StudyParameter& parameter, double u);

}  // namespace mbd
