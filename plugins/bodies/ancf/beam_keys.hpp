// The scene keys every ANCF body type reads the same way (docs/plugin-sdk.md "Bodies"): the
// straight reference line `from` -> `to`, the mesh `elements`, and positive section values, each
// refused at its file:line naming the body. Header-only: shared by the types of this plugin.
#pragma once

#include <mbd/sdk/params.hpp>

#include <Eigen/Core>

#include <string>

namespace mbd::ancf {

// Refuses the value of `key` at its file:line, naming the body (the Params' owner).
[[noreturn]] inline void refuse(const Params& p, const std::string& key, const std::string& message) {
    throw InputError(p.at(key).location(), p.owner() + ": " + message);
}

inline double positive(const Params& p, const std::string& key) {
    const double value = p.number(key);
    if (!(value > 0)) refuse(p, key, "'" + key + "' must be positive, got " + p.at(key).text);
    return value;
}

// The straight reference line of a beam in `dimensions` (2 or 3) and its mesh.
struct BeamLine {
    Eigen::VectorXd from, tangent;  // unit tangent from `from` to `to`
    double length = 0.0;
    int elements = 0;
    double element_length() const { return length / elements; }
};

inline BeamLine read_beam_line(const Params& p, int dimensions) {
    BeamLine line;
    line.from = p.vector("from", dimensions);
    const Eigen::VectorXd to = p.vector("to", dimensions);
    line.length = (to - line.from).norm();
    if (!(line.length > 0))
        refuse(p, "to", "'from' and 'to' coincide: the beam has zero length; give two distinct end points");
    line.tangent = (to - line.from) / line.length;
    line.elements = static_cast<int>(p.integer("elements", 0, 100000));
    if (line.elements < 1)
        refuse(p, "elements", "'elements' must be at least 1: an ANCF beam element needs two nodes");
    return line;
}

// Gauss points of the axial term (`axial_points`, 1 to 5, default 5: exact).
inline int read_axial_points(const Params& p) {
    return static_cast<int>(p.has("axial_points") ? p.integer("axial_points", 1, 5) : 5);
}

}  // namespace mbd::ancf
