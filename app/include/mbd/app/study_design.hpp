// The cases of a study's design (docs/sweep.md, "Designs"): a full grid, a Latin hypercube or
// Monte Carlo samples. Every design is a pure function of the study file (its seed included)
// and of the case's index: any case is made when it is asked for, in any order, with no table
// of the cases in memory (a study of 1e8 cases takes none), and each MPI rank, and a resumed
// run, makes the same cases.
#pragma once

#include <mbd/app/study.hpp>

#include <cstdint>
#include <vector>

namespace mbd {

// Case k holds the parameter values in the order of Study::parameters:
//  - grid: every combination of the value lists, the last parameter varying fastest;
//  - latin_hypercube: per parameter, the `cases` equal-probability strata in a random order
//    (a keyed pseudo-random permutation of 0 .. cases-1) and a random point in each (McKay,
//    Beckman and Conover 1979), through the inverse CDF;
//  - monte_carlo: independent probabilities through the inverse CDF.
// The random numbers are SplitMix64 (Steele, Lea and Flood 2014) of the seed, the parameter
// and the case index, turned into probabilities and permutations here, not by the library's
// distributions (whose results the standard leaves to each implementation): the same on
// every machine.
class CaseDesign {
public:
    // InputError (the study file) for a grid of more than 1e8 cases.
    explicit CaseDesign(const Study& study);
    long cases() const { return cases_; }
    std::vector<double> values(long index) const;

private:
    double probability(std::size_t parameter, int purpose, long index) const;
    std::uint64_t stratum(std::size_t parameter, long index) const;

    std::vector<StudyParameter> parameters_;
    DesignType type_ = DesignType::Grid;
    long cases_ = 0;
    std::uint64_t seed_ = 0;
    int half_bits_ = 1;  // the permutation's domain is 2^(2 half_bits) >= cases
};

// Every case at once (small designs: tests, a look at a design); row k is CaseDesign::values(k).
std::vector<std::vector<double>> design_cases(const Study& study);

// The value of probability u in (0, 1) under the parameter's distribution (inverse CDF).
double inverse_cdf(const StudyParameter& parameter, double u);

}  // namespace mbd
