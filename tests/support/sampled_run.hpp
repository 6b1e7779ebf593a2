// A simulation's output rows kept in memory with their column names (one row per output sample,
// through simulate's callback), and the questions tests ask of them: a column's value, the
// largest change of the total energy (diagnostics on), the largest magnitude of a column.
#pragma once

#include "support/test_support.hpp"

#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace mbd::test {

struct SampledRun {
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;

    // the column's index, -1 when the run has none of that name
    int column(const std::string& name) const {
        const auto it = std::find(columns.begin(), columns.end(), name);
        return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
    }
    // the value in a row; a missing column fails the test (and reads NaN)
    double at(size_t row, const std::string& name) const {
        const int c = column(name);
        if (c < 0) ADD_FAILURE() << "no column " << name;
        return c < 0 ? NAN : rows[row][c];
    }
    double energy(size_t row) const { return at(row, "kinetic_energy") + at(row, "potential_energy"); }
    double largest_energy_change() const {
        double worst = 0.0;
        for (size_t r = 0; r < rows.size(); ++r) worst = std::max(worst, std::abs(energy(r) - energy(0)));
        return worst;
    }
    double largest(const std::string& name) const {
        double worst = 0.0;
        for (size_t r = 0; r < rows.size(); ++r) worst = std::max(worst, std::abs(at(r, name)));
        return worst;
    }
};

// The model run with `settings` (diagnostics turned on for the energy columns).
inline SampledRun run_sampled(const Model& model, SimulationSettings settings) {
    settings.diagnostics = true;
    SampledRun run;
    const SimulationResult result = simulate(model, shared_registry(), settings, [&](const SimulationSample& s) {
        run.rows.push_back(*s.row);
        return true;
    });
    run.columns = result.columns;
    return run;
}

}  // namespace mbd::test
