#include "plugin_check_scenes.hpp"

#include <algorithm>
#include <sstream>

namespace mbd::cli {
namespace {

// The key of a "key: value" line.
std::string key_of(const std::string& line) {
    const size_t colon = line.find(':');
    std::string key = line.substr(0, colon);
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t") + 1);
    return key;
}

// The element's own keys, indented under its list item.
std::string indented(const std::vector<std::string>& keys) {
    std::ostringstream out;
    for (const std::string& line : keys)
        if (!line.empty()) out << "    " << line << "\n";
    return out.str();
}

// A random point in body axes, written for a scene (non-zero offsets from the mass centre).
std::string random_point(Dimension d, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::ostringstream s;
    s.precision(17);
    s << "[" << u(rng) << ", " << u(rng);
    if (d == Dimension::Spatial) s << ", " << u(rng);
    s << "]";
    return s.str();
}

const char* const planar_bodies =
    "  - {name: a, mass: 1.3, inertia: 0.2, position: [0.3, 0.1], angle: 0.2}\n"
    "  - {name: b, mass: 0.7, inertia: 0.1, position: [0.8, -0.2], angle: -0.4}\n";
const char* const spatial_bodies =
    "  - {name: a, mass: 1.3, inertia: [0.2, 0.3, 0.4], position: [0.3, 0.1, 0.2], "
    "orientation: {axis: [1, 2, 3], angle: 0.5}}\n"
    "  - {name: b, mass: 0.7, inertia: [0.1, 0.2, 0.25], position: [0.8, -0.2, 0.1], "
    "orientation: {axis: [-1, 0.5, 2], angle: 1.1}}\n";

}  // namespace

std::vector<std::string> element_keys(const PluginDescription* description, Dimension d,
                                      const std::vector<std::string>& params) {
    std::vector<std::string> lines, given;
    for (const std::string& line : params)
        if (!line.empty()) {
            lines.push_back(line);
            given.push_back(key_of(line));
        }
    if (!description) return lines;
    for (int k = 0; k < description->key_count(); ++k) {
        const PluginKey& key = description->keys[k];
        const bool wanted = !key.default_value || (key.in_check && given.empty());
        if (!wanted || !key.example || std::find(given.begin(), given.end(), key.name) != given.end()) continue;
        const char* value = d == Dimension::Spatial && key.example_spatial ? key.example_spatial : key.example;
        lines.push_back(std::string(key.name) + ": " + value);
    }
    return lines;
}

std::string joint_scene(Dimension d, const std::string& type, const std::vector<std::string>& keys, bool with_points) {
    std::ostringstream s;
    const std::string points = !with_points ? ""
                               : d == Dimension::Planar ? "    points: [[0.1, 0.2], [0.3, -0.1]]\n"
                                                        : "    points: [[0.1, 0.2, 0.3], [0.3, -0.1, 0.2]]\n";
    if (d == Dimension::Planar) {
        s << "dimension: planar\nbodies:\n" << planar_bodies << "joints:\n"
          << "  - name: to_ground\n    type: " << type << "\n    bodies: [ground, a]\n    point: [0.1, 0.05]\n"
          << "    axis: [0.6, 0.8]\n" << points << indented(keys)
          << "  - name: between\n    type: " << type << "\n    bodies: [a, b]\n    point: [0.5, 0.0]\n"
          << "    axis: [0.6, 0.8]\n" << points << indented(keys);
    } else {
        s << "dimension: spatial\nbodies:\n" << spatial_bodies << "joints:\n";
        for (const char* name : {"to_ground", "between"}) {
            s << "  - name: " << name << "\n    type: " << type << "\n    bodies: "
              << (std::string(name) == "to_ground" ? "[ground, a]" : "[a, b]")
              << "\n    point: [0.5, 0.1, 0.2]\n    axes: [[0.3, 0.4, 0.866], [0.8, -0.6, 0.0]]\n"
              << points << indented(keys);
        }
    }
    return s.str();
}

std::string force_scene(Dimension d, const std::string& type, const std::vector<std::string>& keys, bool two_bodies,
                        std::mt19937& rng) {
    std::ostringstream s;
    const bool planar = d == Dimension::Planar;
    s << "dimension: " << (planar ? "planar" : "spatial") << "\n";
    if (type == "gravity") s << "gravity: " << (planar ? "[0.3, -9.81]" : "[0.3, -9.81, 0.2]") << "\n";
    s << "bodies:\n" << (planar ? planar_bodies : spatial_bodies);
    if (type == "gravity") return s.str();
    s << "forces:\n  - name: element\n    type: " << type << "\n";
    if (two_bodies)
        s << "    bodies: [a, b]\n    points: [" << random_point(d, rng) << ", " << random_point(d, rng) << "]\n";
    else
        s << "    body: a\n    point: " << random_point(d, rng) << "\n";
    s << indented(keys);
    return s.str();
}

}  // namespace mbd::cli
