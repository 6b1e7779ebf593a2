// Settings and small helpers shared by the two paths of the embedding formulation.
#pragma once

#include <mbd/sdk/system.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace mbd::embedding {

struct Settings {
    std::string path = "auto";            // auto | dense | recursive
    double pivot_threshold = 0.1;         // initial selection: threshold pivoting (partition.hpp)
    double reselect_ratio = 0.05;         // re-select when J_d's pivot ratio falls below this (book Sec. 6.12)
    double rank_tolerance = 1e-10;        // relative: rows below this after elimination are redundant
    double newton_tolerance = 1e-12;      // |C| of the dependent-position Newton-Raphson (scaled by the coordinates)
    int newton_iterations = 25;
    std::vector<std::string> independent; // optional initial independent velocity components ("crank.angle")
    bool log = true;                      // path choice, redundant rows and re-selections on std::clog
};

inline std::string format_time(double t) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.10g", t);
    return buffer;
}

// Names of the velocity components: planar body.x, body.y, body.angle; spatial body.x,
// body.y, body.z (mass-centre velocity, world) and body.wx, body.wy, body.wz (angular
// velocity in body axes).
inline std::vector<std::string> velocity_names(const System& system) {
    static const char* planar[] = {"x", "y", "angle"};
    static const char* spatial[] = {"x", "y", "z", "wx", "wy", "wz"};
    const bool is_planar = system.dimension() == Dimension::Planar;
    std::vector<std::string> names;
    for (int b = 0; b < system.body_count(); ++b)
        for (int c = 0; c < (is_planar ? 3 : 6); ++c)
            names.push_back(system.body(b).name + "." + (is_planar ? planar[c] : spatial[c]));
    return names;
}

}  // namespace mbd::embedding
