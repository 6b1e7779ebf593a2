// The coordinate-partition options shared by the formulations that partition the
// coordinates (embedding, amalgamated, hamiltonian): see partition.hpp for what the
// pivot threshold and the rank tolerance mean. Part of FormulationOptions
// (formulation_options.hpp, group kPartitionOptions).
#pragma once

namespace mbd {

struct PartitionSettings {
    double pivot_threshold = 0.1;  // initial selection: threshold pivoting (partition.hpp), in (0, 1]
    double reselect_ratio = 0.05;  // re-select when J_d's pivot ratio falls below this (book Sec. 6.12)
    double rank_tolerance = 1e-10; // relative: rows below this after elimination are redundant
};

}  // namespace mbd
