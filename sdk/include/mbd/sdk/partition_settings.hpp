// The coordinate-partition options shared by the formulations that partition the
// coordinates (embedding, amalgamated, hamiltonian): see partition.hpp for what the
// pivot threshold and the rank tolerance mean.
#pragma once

#include <mbd/sdk/params.hpp>

#include <string>

namespace mbd {

struct PartitionSettings {
    double pivot_threshold = 0.1;  // initial selection: threshold pivoting (partition.hpp)
    double reselect_ratio = 0.05;  // re-select when J_d's pivot ratio falls below this (book Sec. 6.12)
    double rank_tolerance = 1e-10; // relative: rows below this after elimination are redundant
    bool log = false;              // re-selections (and the like) in FormulationOptions::log

    // pivot_threshold, reselect_ratio, rank_tolerance (each only when present)
    void read(const Params& params) {
        if (params.has("pivot_threshold")) {
            pivot_threshold = params.positive("pivot_threshold");
            if (pivot_threshold > 1.0) params.at("pivot_threshold").fail("'pivot_threshold' must be in (0, 1]");
        }
        if (params.has("reselect_ratio")) reselect_ratio = params.non_negative("reselect_ratio", 0.05);
        if (params.has("rank_tolerance")) rank_tolerance = params.positive("rank_tolerance");
    }

    // log: true or false (only when present); separate from read() so that each
    // formulation keeps the order in which it checks its keys
    void read_log(const Params& params) {
        if (params.has("log")) {
            const std::string v = params.string("log");
            if (v != "true" && v != "false") params.at("log").fail("'log' must be true or false");
            log = v == "true";
        }
    }
};

}  // namespace mbd
