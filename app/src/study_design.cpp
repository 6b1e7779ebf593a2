// Grid, Latin hypercube and Monte Carlo designs (study_design.hpp).
#include <mbd/app/study_design.hpp>

#include <mbd/sdk/params.hpp>

#include <boost/math/special_functions/erf.hpp>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>

namespace mbd {

namespace {

// A probability in (0, 1) from 53 random bits, never 0 or 1 (the inverse CDFs are finite there).
double probability(std::mt19937_64& rng) { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1p-53; }

// Uniform in [0, n), unbiased (the top partial range of 2^64 is rejected).
std::uint64_t below(std::mt19937_64& rng, std::uint64_t n) {
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    std::uint64_t x = rng();
    while (x >= limit) x = rng();
    return x % n;
}

std::vector<std::vector<double>> grid(const Study& study) {
    std::size_t total = 1;
    for (const StudyParameter& p : study.parameters) {
        total *= p.values.size();
        if (total > 100000000) throw InputError(study.file.string(), "the grid has more than 1e8 cases");
    }
    std::vector<std::vector<double>> cases(total, std::vector<double>(study.parameters.size()));
    for (std::size_t k = 0; k < total; ++k) {
        std::size_t rest = k;
        for (std::size_t j = study.parameters.size(); j-- > 0;) {
            const std::vector<double>& values = study.parameters[j].values;
            cases[k][j] = values[rest % values.size()];
            rest /= values.size();
        }
    }
    return cases;
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

std::vector<std::vector<double>> design_cases(const Study& study) {
    if (study.design.type == DesignType::Grid) return grid(study);
    const std::size_t n = static_cast<std::size_t>(study.design.cases), d = study.parameters.size();
    std::mt19937_64 rng(study.design.seed);
    std::vector<std::vector<double>> cases(n, std::vector<double>(d));
    if (study.design.type == DesignType::MonteCarlo) {
        for (std::size_t k = 0; k < n; ++k)
            for (std::size_t j = 0; j < d; ++j) cases[k][j] = inverse_cdf(study.parameters[j], probability(rng));
        return cases;
    }
    std::vector<std::uint64_t> strata(n);
    for (std::size_t j = 0; j < d; ++j) {
        std::iota(strata.begin(), strata.end(), 0);
        for (std::size_t k = n; k > 1; --k) std::swap(strata[k - 1], strata[below(rng, k)]);  // Fisher-Yates
        for (std::size_t k = 0; k < n; ++k) {
            const double u = std::min((static_cast<double>(strata[k]) + probability(rng)) / static_cast<double>(n),
                                      1.0 - 0x1p-53);
            cases[k][j] = inverse_cdf(study.parameters[j], u);
        }
    }
    return cases;
}

}  // namespace mbd
