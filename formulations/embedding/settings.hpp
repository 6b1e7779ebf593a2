// Settings and small helpers shared by the two paths of the embedding formulation.
#pragma once

#include <mbd/sdk/partition_settings.hpp>
#include <mbd/sdk/system.hpp>
#include <mbd/sdk/text.hpp>  // format_time

#include <string>
#include <vector>

namespace mbd::embedding {

// pivot_threshold, reselect_ratio, rank_tolerance and log come from PartitionSettings;
// log (path choice, redundant rows and re-selections, in FormulationOptions::log) defaults to true here.
struct Settings : PartitionSettings {
    Settings() { log = true; }

    std::string path = "auto";            // auto | dense | recursive
    double newton_tolerance = 1e-12;      // |C| of the dependent-position Newton-Raphson (scaled by the coordinates)
    int newton_iterations = 25;
    std::vector<std::string> independent; // optional initial independent velocity components ("crank.angle")
};

// Names of the velocity components: planar body.x, body.y, body.angle; spatial body.x,
// body.y, body.z (mass-centre velocity, world) and body.wx, body.wy, body.wz (angular
// velocity in body axes).
inline std::vector<std::string> velocity_names(System& system) {
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
