// Command line and output of the peer programs (protocol of core/src/bench.cpp):
//   mbd_peer_<engine> MODEL[:INTEGRATOR] T_END OUTPUT_STEP tol|step VALUE
// prints "cpu_s steps" and then one line "t x1 y1 z1 [x2 y2 z2 ...]" per output time
// (output_step, 2 output_step, ..., t_end) with the measured points of the model (the
// same points as the scene's bench measure). Models: pendulum_a01, four_bar_2, chain_5, chain_50.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

struct PeerArgs {
    std::string model, integrator;
    double t_end = 0, output_step = 0, value = 0;
    bool tolerance = true;
};

inline PeerArgs parse_peer_args(int argc, char** argv) {
    if (argc != 6) {
        std::fprintf(stderr, "usage: %s MODEL[:INTEGRATOR] T_END OUTPUT_STEP tol|step VALUE\n", argv[0]);
        std::exit(2);
    }
    PeerArgs a;
    a.model = argv[1];
    const auto colon = a.model.find(':');
    if (colon != std::string::npos) {
        a.integrator = a.model.substr(colon + 1);
        a.model = a.model.substr(0, colon);
    }
    a.t_end = std::atof(argv[2]);
    a.output_step = std::atof(argv[3]);
    a.tolerance = std::string(argv[4]) == "tol";
    a.value = std::atof(argv[5]);
    return a;
}

inline std::vector<double> peer_output_times(const PeerArgs& a) {
    const long n = std::max(1L, std::lround(a.t_end / a.output_step));
    std::vector<double> t;
    for (long k = 1; k < n; ++k) t.push_back(k * a.output_step);
    t.push_back(a.t_end);
    return t;
}

// Measured links of chain_N (the scene's bench measure, scripts/gen_bench_scenes.py): the tip
// for short chains, else the ends of links 5, N/2 and N.
inline std::vector<int> chain_measured(int n) {
    if (n <= 5) return {n - 1};
    return {4, n / 2 - 1, n - 1};
}

inline int chain_links(const std::string& model) {
    return model.rfind("chain_", 0) == 0 ? std::atoi(model.c_str() + 6) : 0;
}
