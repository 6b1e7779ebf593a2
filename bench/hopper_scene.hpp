// The hopper of issue 39 (docs/benchmarks.md "The hopper against MuJoCo"): spheres and a few
// boxes falling through the square opening of a box-shaped hopper into a bin, written once as an
// mbd scene and once as MJCF from the same list of bodies, so both engines get the same radii,
// masses, inertias, initial positions and friction, and contact laws matched as docs/benchmarks.md
// explains (mujoco_contact below). Header-only: bench_hopper writes both files, and
// tests/test_bench_hopper.cpp checks that they describe the same bodies.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace hopper {

struct Spec {
    int spheres = 1000, boxes = 10;
    double radius = 0.01, sphere_mass = 0.01;                       // m, kg
    double box_x = 0.03, box_y = 0.02, box_z = 0.02, box_mass = 0.02;  // edge lengths, kg
    double half_width = 0.12;  // the hopper's inner half-width (square), m
    double opening = 0.06;     // the opening's half-width (square, centred in the floor), m
    double floor_z = 0.3;      // the height of the opening's edge (the floor's top there), m
    // the floor's four plates rise from the opening to the walls at this angle: steeper than a
    // box's friction angle (atan 0.5 = 26.6 deg), so the hopper can empty (a flat floor keeps
    // its ledges full)
    double slope = 35 * M_PI / 180;
    double wall_top = 0.7, wall = 0.01;  // the top of its walls; wall and floor thickness
    double bin_half_width = 0.25, bin_height = 0.15;  // the bin on the ground (z = 0)
    // mbd's Hunt-Crossley law of every body: F = k delta^1.5 (1 + damping), e at impact_velocity
    double stiffness = 1e6, restitution = 0.5, impact_velocity = 1.0;
    double friction = 0.5, stiction_velocity = 0.01;  // Coulomb coefficient (static = kinetic)
    double gravity = 9.81;
};

struct Body {
    std::string name;
    bool box = false;
    double mass = 0.0;
    double inertia[3] = {0, 0, 0};  // principal, about the mass centre, body axes
    double x = 0, y = 0, z = 0;     // initial position, world (at rest, axes aligned)
};

// A static box of the ground: half extents and centre.
struct Slab {
    double hx, hy, hz, x, y, z;
    double ax = 1, ay = 0, az = 0, angle = 0;  // its axes turned by angle (rad) about (ax, ay, az)
};

// The floor's rise from the opening's edge to the wall.
inline double floor_rise(const Spec& s) { return (s.half_width - s.opening) * std::tan(s.slope); }

inline std::string num(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

// The spheres in layers of a square grid above the floor (a small deterministic jitter breaks the
// grid's symmetry), the boxes in a layer above them.
inline std::vector<Body> bodies(const Spec& s) {
    std::vector<Body> out;
    const double spacing = 2 * s.radius + 0.003;
    const int side = static_cast<int>(std::floor((2 * s.half_width - 2 * s.radius) / spacing)) + 1;
    const double first = -0.5 * spacing * (side - 1);
    unsigned seed = 12345;
    auto jitter = [&] {  // +-0.5 mm, a linear congruential generator: the same on every platform
        seed = seed * 1103515245u + 12345u;
        return 1e-3 * (((seed >> 16) & 0x7fff) / 32767.0 - 0.5);
    };
    for (int k = 0; k < s.spheres; ++k) {
        Body b;
        b.name = "s" + std::to_string(k);
        b.mass = s.sphere_mass;
        b.inertia[0] = b.inertia[1] = b.inertia[2] = 0.4 * s.sphere_mass * s.radius * s.radius;
        const int layer = k / (side * side), cell = k % (side * side);
        b.x = first + spacing * (cell % side) + jitter();
        b.y = first + spacing * (cell / side) + jitter();
        b.z = s.floor_z + floor_rise(s) + s.radius + 0.002 + spacing * layer;
        out.push_back(b);
    }
    const double top = s.floor_z + floor_rise(s) + 0.002 + spacing * ((s.spheres + side * side - 1) / (side * side)) + s.box_z;
    for (int k = 0; k < s.boxes; ++k) {
        Body b;
        b.name = "b" + std::to_string(k);
        b.box = true;
        b.mass = s.box_mass;
        const double x2 = s.box_x * s.box_x, y2 = s.box_y * s.box_y, z2 = s.box_z * s.box_z;
        b.inertia[0] = s.box_mass * (y2 + z2) / 12;
        b.inertia[1] = s.box_mass * (x2 + z2) / 12;
        b.inertia[2] = s.box_mass * (x2 + y2) / 12;
        b.x = -0.08 + 0.04 * (k % 5);
        b.y = -0.03 + 0.06 * ((k / 5) % 2);
        b.z = top + 0.03 * (k / 10);
        out.push_back(b);
    }
    return out;
}

// The hopper (four walls; a floor of four plates sloping down to the opening, each a slab whose
// top face runs from the opening's edge at floor_z up to the wall) and the bin's four walls.
inline std::vector<Slab> slabs(const Spec& s) {
    const double a = s.half_width, o = s.opening, t = s.wall, c = std::cos(s.slope), n = std::sin(s.slope);
    const double wall_h = 0.5 * (s.wall_top - (s.floor_z - t)), wall_z = 0.5 * (s.wall_top + s.floor_z - t);
    const double half_run = 0.5 * (a - o) / c;  // half the plate's width along its slope
    const double at = 0.5 * (a + o) + 0.5 * t * n, mid_z = s.floor_z + 0.5 * floor_rise(s) - 0.5 * t * c;
    const double b = s.bin_half_width;
    return {{a + t, 0.5 * t, wall_h, 0, a + 0.5 * t, wall_z},  {a + t, 0.5 * t, wall_h, 0, -a - 0.5 * t, wall_z},
            {0.5 * t, a, wall_h, a + 0.5 * t, 0, wall_z},      {0.5 * t, a, wall_h, -a - 0.5 * t, 0, wall_z},
            {a, half_run, 0.5 * t, 0, at, mid_z, 1, 0, 0, s.slope},
            {a, half_run, 0.5 * t, 0, -at, mid_z, 1, 0, 0, -s.slope},
            {half_run, a, 0.5 * t, at, 0, mid_z, 0, 1, 0, -s.slope},
            {half_run, a, 0.5 * t, -at, 0, mid_z, 0, 1, 0, s.slope},
            {b + t, 0.5 * t, 0.5 * s.bin_height, 0, b + 0.5 * t, 0.5 * s.bin_height},
            {b + t, 0.5 * t, 0.5 * s.bin_height, 0, -b - 0.5 * t, 0.5 * s.bin_height},
            {0.5 * t, b, 0.5 * s.bin_height, b + 0.5 * t, 0, 0.5 * s.bin_height},
            {0.5 * t, b, 0.5 * s.bin_height, -b - 0.5 * t, 0, 0.5 * s.bin_height}};
}

inline std::string mbd_scene(const Spec& s) {
    std::ostringstream y;
    const std::string friction = "static_friction: " + num(s.friction) + ", kinetic_friction: " + num(s.friction) +
                                 ", stiction_velocity: " + num(s.stiction_velocity);
    const std::string material = "{stiffness: " + num(s.stiffness) + ", restitution: " + num(s.restitution) +
                                 ", impact_velocity: " + num(s.impact_velocity) + ", " + friction + "}";
    y << "name: hopper\ndimension: spatial\ngravity: [0, 0, " << num(-s.gravity) << "]\n"
      << "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1], material: {" << friction << "}}\n";
    for (const Slab& w : slabs(s))  // rigid (no stiffness): each pair has the body's own law
        y << "    - {shape: box, size: [" << num(2 * w.hx) << ", " << num(2 * w.hy) << ", " << num(2 * w.hz)
          << "], position: [" << num(w.x) << ", " << num(w.y) << ", " << num(w.z) << "], orientation: {axis: ["
          << num(w.ax) << ", " << num(w.ay) << ", " << num(w.az) << "], angle: " << num(w.angle) << "}, material: {"
          << friction << "}}\n";
    y << "bodies:\n";
    for (const Body& b : bodies(s)) {
        y << "  - {name: " << b.name << ", mass: " << num(b.mass) << ", inertia: [" << num(b.inertia[0]) << ", "
          << num(b.inertia[1]) << ", " << num(b.inertia[2]) << "], position: [" << num(b.x) << ", " << num(b.y)
          << ", " << num(b.z) << "],\n     collision: [{shape: ";
        if (b.box)
            y << "box, size: [" << num(s.box_x) << ", " << num(s.box_y) << ", " << num(s.box_z) << "]";
        else
            y << "sphere, radius: " << num(s.radius);
        y << ", material: " << material << "}]}\n";
    }
    return y.str();
}

// MuJoCo's soft contact matched to mbd's law (docs/benchmarks.md): solref's direct form
// "-K -B" with a constant impedance d = solimp's 0.0001 makes the normal acceleration
// a = (1 - d) a0 - K r - B rdot, a linear spring-damper per unit mass. K is the Hunt-Crossley
// law's slope 1.5 k delta^0.5 at a sphere's resting depth delta = (m g / k)^(2/3), over m; B
// gives a linear oscillator of that frequency the restitution e.
struct MujocoContact {
    double K = 0.0, B = 0.0;
};

inline MujocoContact mujoco_contact(const Spec& s) {
    const double delta = std::pow(s.sphere_mass * s.gravity / s.stiffness, 2.0 / 3.0);
    const double K = 1.5 * s.stiffness * std::sqrt(delta) / s.sphere_mass;
    const double log_e = std::log(s.restitution);
    const double zeta = -log_e / std::sqrt(M_PI * M_PI + log_e * log_e);
    return {K, 2 * zeta * std::sqrt(K)};
}

inline std::string mjcf(const Spec& s, double timestep) {
    const MujocoContact c = mujoco_contact(s);
    std::ostringstream x;
    // elliptic cones (Coulomb's circle, as mbd's friction; 3 rows a contact), room for 2 contacts
    // a body: MuJoCo 2.2 allocates njmax x njmax and njmax x nv arrays and cannot make an mjData
    // of 2 GB or more (3 contacts a body, njmax = 9,090, failed for 1,010 bodies); a run that
    // needs more stops with MuJoCo's warning (peer_mujoco_hopper)
    x << "<mujoco model=\"hopper\">\n  <compiler angle=\"radian\"/>\n  <option timestep=\"" << num(timestep)
      << "\" integrator=\"Euler\" cone=\"elliptic\" gravity=\"0 0 " << num(-s.gravity) << "\"/>\n  <size nconmax=\""
      << 2 * (s.spheres + s.boxes) << "\" njmax=\"" << 6 * (s.spheres + s.boxes) << "\"/>\n"
      << "  <custom><numeric name=\"hopper_floor\" data=\"" << num(s.floor_z) << "\"/><numeric name=\"radius\" data=\""
      << num(s.radius) << "\"/><numeric name=\"wall\" data=\"" << num(s.wall) << "\"/></custom>\n"
      << "  <default><geom condim=\"3\" friction=\"" << num(s.friction) << " 0 0\" solref=\"" << num(-c.K) << " "
      << num(-c.B) << "\" solimp=\"0.0001 0.0001 0.001\"/></default>\n  <worldbody>\n"
      << "    <geom name=\"floor\" type=\"plane\" size=\"0 0 1\"/>\n";
    for (const Slab& w : slabs(s))
        x << "    <geom type=\"box\" size=\"" << num(w.hx) << " " << num(w.hy) << " " << num(w.hz) << "\" pos=\""
          << num(w.x) << " " << num(w.y) << " " << num(w.z) << "\" axisangle=\"" << num(w.ax) << " " << num(w.ay) << " "
          << num(w.az) << " " << num(w.angle) << "\"/>\n";
    for (const Body& b : bodies(s)) {
        x << "    <body name=\"" << b.name << "\" pos=\"" << num(b.x) << " " << num(b.y) << " " << num(b.z)
          << "\"><freejoint/><inertial pos=\"0 0 0\" mass=\"" << num(b.mass) << "\" diaginertia=\"" << num(b.inertia[0])
          << " " << num(b.inertia[1]) << " " << num(b.inertia[2]) << "\"/>";
        if (b.box)
            x << "<geom type=\"box\" size=\"" << num(0.5 * s.box_x) << " " << num(0.5 * s.box_y) << " "
              << num(0.5 * s.box_z) << "\"/>";
        else
            x << "<geom type=\"sphere\" size=\"" << num(s.radius) << "\"/>";
        x << "</body>\n";
    }
    x << "  </worldbody>\n</mujoco>\n";
    return x.str();
}

// The outcome both engines report from the spheres' heights: the fraction below the hopper's
// floor (out of the hopper), and the pile's height, the 95th percentile of those spheres' tops.
struct Outcome {
    double out_fraction = 0.0, pile_height = 0.0;
};

inline Outcome outcome(const Spec& s, std::vector<double> sphere_z) {
    std::vector<double> tops;
    for (double z : sphere_z)
        if (z < s.floor_z - s.wall - s.radius) tops.push_back(z + s.radius);
    Outcome o;
    o.out_fraction = sphere_z.empty() ? 0.0 : static_cast<double>(tops.size()) / sphere_z.size();
    if (!tops.empty()) {
        std::sort(tops.begin(), tops.end());
        o.pile_height = tops[static_cast<size_t>(0.95 * (tops.size() - 1))];
    }
    return o;
}

}  // namespace hopper
