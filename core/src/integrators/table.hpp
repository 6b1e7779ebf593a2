// The integrators' table (table.cpp): each row describes one integrator once and names the
// function that makes it. Adding an integrator is its own file, defining its make function
// in mbd::integrators, plus one row of kIntegratorTable.
#pragma once

#include <mbd/integrator.hpp>

#include <memory>

namespace mbd::integrators {

using MakeIntegrator = std::unique_ptr<Integrator> (*)(const IntegratorSettings&);

struct IntegratorRow {
    IntegratorDescription description;
    MakeIntegrator make;
};

// Every row, in the order the integrators are listed to the user.
const std::vector<IntegratorRow>& integrator_table();

}  // namespace mbd::integrators
