// Grid, Latin hypercube and Monte Carlo designs, case by case (study_design.hpp).
#include <mbd/app/study_design.hpp>

#include <mbd/sdk/params.hpp>

#include <boost/math/special_functions/erf.hpp>

#include <algorithm>
#include <cmath>

namespace mbd {

namespace {

constexpr long kMostCases = 100000000;

// SplitMix64's output function: a bijective mix of 64 bits whose outputs for consecutive
// inputs spaced by kGamma are the SplitMix64 sequence.
std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
constexpr std::uint64_t kGamma = 0x9e3779b97f4a7c15ULL;

// The n-th number of the SplitMix64 stream `key`: random access into the sequence.
std::uint64_t draw(std::uint64_t key, std::uint64_t n) { return mix(key + (n + 1) * kGamma); }

// The stream of one parameter and purpose (0: the probability, 1: the strata permutation).
std::uint64_t stream_key(std::uint64_t seed, std::size_t parameter, int purpose) {
    return mix(mix(seed) + (2 * parameter + static_cast<std::uint64_t>(purpose) + 1) * 0xd1b54a32d192ed03ULL);
}

// A probability in (0, 1) from 53 random bits, never 0 or 1 (the inverse CDFs are finite there).
double to_probability(std::uint64_t bits) { return (static_cast<double>(bits >> 11) + 0.5) * 0x1p-53; }

long grid_cases(const Study& study) {
    long total = 1;
    for (const StudyParameter& p : study.parameters) {
        total *= static_cast<long>(p.values.size());
        if (total > kMostCases) throw InputError(study.file.string(), "the grid has more than 1e8 cases");
    }
    return total;
}

}  // namespace

double inverse_cdf(const StudyParameter& p, double u) {
    if (p.distribution == "uniform") return p.a + (p.b - p.a) * u;
    if (p.distribution == "normal") return p.a + p.b * std::sqrt(2.0) * boost::math::erf_inv(2.0 * u - 1.0);
    if (p.distribution == "lognormal") return std::exp(p.a + p.b * std::sqrt(2.0) * boost::math::erf_inv(2.0 * u - 1.0));
    // triangular on [a, c] with mode b
    const double split = (p.b - p.a) / (p.c - p.a);
    return u < split ? p.a + std::sqrt(u * (p.c - p.a) * (p.b - p.a))
                     : p.c - std::sqrt((1.0 - u) * (p.c - p.a) * (p.c - p.b));
}

CaseDesign::CaseDesign(const Study& study)
    : parameters_(study.parameters), type_(study.design.type), seed_(study.design.seed) {
    cases_ = type_ == DesignType::Grid ? grid_cases(study) : study.design.cases;
    while ((std::uint64_t{1} << (2 * half_bits_)) < static_cast<std::uint64_t>(cases_)) ++half_bits_;
}

double CaseDesign::probability(std::size_t parameter, int purpose, long index) const {
    return to_probability(draw(stream_key(seed_, parameter, purpose), static_cast<std::uint64_t>(index)));
}

// The stratum of case `index` for one parameter: a keyed permutation of 0 .. cases-1, a
// four-round Feistel network on 2 half_bits_ bits walked along its cycle until it falls below
// `cases` (the domain is less than four times `cases`, so a few steps on average).
std::uint64_t CaseDesign::stratum(std::size_t parameter, long index) const {
    const std::uint64_t key = stream_key(seed_, parameter, 1), mask = (std::uint64_t{1} << half_bits_) - 1;
    std::uint64_t x = static_cast<std::uint64_t>(index);
    do {
        std::uint64_t left = x >> half_bits_, right = x & mask;
        for (std::uint64_t round = 0; round < 4; ++round) {
            const std::uint64_t next = left ^ (draw(key + round, right) & mask);
            left = right;
            right = next;
        }
        x = (left << half_bits_) | right;
    } while (x >= static_cast<std::uint64_t>(cases_));
    return x;
}

std::vector<double> CaseDesign::values(long index) const {
    std::vector<double> out(parameters_.size());
    if (type_ == DesignType::Grid) {
        long rest = index;
        for (std::size_t j = parameters_.size(); j-- > 0;) {
            const std::vector<double>& values = parameters_[j].values;
            out[j] = values[static_cast<std::size_t>(rest % static_cast<long>(values.size()))];
            rest /= static_cast<long>(values.size());
        }
        return out;
    }
    for (std::size_t j = 0; j < parameters_.size(); ++j) {
        double u = probability(j, 0, index);
        if (type_ == DesignType::LatinHypercube)
            u = std::min((static_cast<double>(stratum(j, index)) + u) / static_cast<double>(cases_), 1.0 - 0x1p-53);
        out[j] = inverse_cdf(parameters_[j], u);
    }
    return out;
}

std::vector<std::vector<double>> design_cases(const Study& study) {
    const CaseDesign design(study);
    std::vector<std::vector<double>> cases;
    cases.reserve(static_cast<std::size_t>(design.cases()));
    for (long k = 0; k < design.cases(); ++k) cases.push_back(design.values(k));
    return cases;
}

}  // namespace mbd
