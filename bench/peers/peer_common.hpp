// Command line and output of the peer programs (protocol of app/src/bench.cpp):
//   mbd_peer_<engine> MODEL[:INTEGRATOR] T_END OUTPUT_STEP tol|step VALUE [BODIES VELOCITIES]
// prints "cpu_s steps" and then one line "t x1 y1 z1 [x2 y2 z2 ...]" per output time
// (output_step, 2 output_step, ..., t_end) with the measured points of the model (the
// same points as the scene's bench measure). Models: pendulum_a01, four_bar_N (IFToMM A02 with N
// four-bar loops), chain_N, gyroscope, bricard, flyball, car_axis, or a model file (URDF, MJCF)
// read by the peer's own reader: then BODIES names the bodies whose mass centres are measured
// (comma-separated) and VELOCITIES the initial joint velocities ("-" for none; else
// comma-separated JOINT=V or JOINT=V1/V2/..., MuJoCo's qvel convention, docs/benchmarks.md).
// A peer that cannot express a model exits with status 2 and says why on stderr.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

struct PeerArgs {
    std::string model, integrator;
    double t_end = 0, output_step = 0, value = 0;
    bool tolerance = true;
    // a model file's measured bodies and initial joint velocities (joint name, its numbers)
    std::vector<std::string> bodies;
    std::vector<std::pair<std::string, std::vector<double>>> velocities;
};

inline std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> out;
    size_t from = 0;
    for (size_t at = text.find(separator); at != std::string::npos; at = text.find(separator, from = at + 1))
        out.push_back(text.substr(from, at - from));
    out.push_back(text.substr(from));
    return out;
}

inline PeerArgs parse_peer_args(int argc, char** argv) {
    if (argc != 6 && argc != 8) {
        std::fprintf(stderr, "usage: %s MODEL[:INTEGRATOR] T_END OUTPUT_STEP tol|step VALUE [BODIES VELOCITIES]\n", argv[0]);
        std::exit(2);
    }
    PeerArgs a;
    a.model = argv[1];
    const auto colon = a.model.rfind(':');
    if (colon != std::string::npos && a.model.find('/', colon) == std::string::npos) {
        a.integrator = a.model.substr(colon + 1);
        a.model = a.model.substr(0, colon);
    }
    a.t_end = std::atof(argv[2]);
    a.output_step = std::atof(argv[3]);
    a.tolerance = std::string(argv[4]) == "tol";
    a.value = std::atof(argv[5]);
    if (argc == 8) {
        a.bodies = split(argv[6], ',');
        if (std::string(argv[7]) != "-")
            for (const std::string& item : split(argv[7], ',')) {
                const auto eq = item.find('=');
                std::vector<double> v;
                for (const std::string& x : split(item.substr(eq + 1), '/')) v.push_back(std::atof(x.c_str()));
                a.velocities.push_back({item.substr(0, eq), v});
            }
    }
    return a;
}

// A model file (URDF or MJCF) rather than a model name.
inline bool is_model_file(const std::string& model) {
    auto ends = [&](const char* e) {
        const std::string x(e);
        return model.size() > x.size() && model.compare(model.size() - x.size(), x.size(), x) == 0;
    };
    return ends(".urdf") || ends(".xml") || ends(".URDF") || ends(".XML");
}

inline std::vector<double> peer_output_times(const PeerArgs& a) {
    const long n = std::max(1L, std::lround(a.t_end / a.output_step));
    std::vector<double> t;
    for (long k = 1; k < n; ++k) t.push_back(k * a.output_step);
    t.push_back(a.t_end);
    return t;
}

// The peer's answer on stdout, read by `mbd bench`: "CPU_SECONDS STEPS", then one row per output
// time (t, then the measured points' coordinates), each number to the last bit.
inline void print_peer_result(double cpu, long steps, const std::vector<std::vector<double>>& rows) {
    std::printf("%.9g %ld\n", cpu, steps);
    for (const auto& row : rows) {
        for (size_t k = 0; k < row.size(); ++k) std::printf(k ? " %.17g" : "%.17g", row[k]);
        std::printf("\n");
    }
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

// N of four_bar_N (IFToMM A02: N+1 cranks, N couplers), 0 for other models.
inline int four_bar_loops(const std::string& model) {
    return model.rfind("four_bar_", 0) == 0 ? std::atoi(model.c_str() + 9) : 0;
}

// The bump angle of the Test Set car axis (scenes/bench/car-axis.yaml, plugins/joints/caraxis_bump): the
// bump point b(t), y_b = r sin(w t), lies on the circle of radius L about the origin at the angle
// phi(t) = asin(r sin(w t) / L). Returns phi and its first two time derivatives.
struct BumpAngle {
    double phi, phid, phidd;
};

inline BumpAngle car_axis_bump_angle(double t, double r = 0.1, double w = 10.0, double L = 1.0) {
    const double u = r / L * std::sin(w * t), ud = r / L * w * std::cos(w * t), udd = -w * w * u;
    const double root = std::sqrt(1.0 - u * u);
    return {std::asin(u), ud / root, udd / root + u * ud * ud / (root * root * root)};
}

// Data of scenes/bench/a05-flyball.yaml shared by the peers (world frame at t = 0, z up; every
// body frame at its mass centre and parallel to the world frame; the left arm at x > 0).
namespace flyball {
constexpr double spin_rate = 6.28318530717959;  // shaft driven at 2 pi rad/s about z
constexpr double shaft_mass = 0.3, shaft_com_z = 0.5;
constexpr double shaft_inertia[3] = {0.025, 0.025, 5e-06};
constexpr double pivot_z = 1.0;  // both arms pinned to the shaft top, axis y
constexpr double arm_mass = 5.3;
constexpr double arm_com[3] = {0.485849056603774, 0.0, 0.158484749152857};  // left arm; right: x -> -x
// left arm centroidal inertia (xx, yy, zz, xy, xz, yz), matrix elements; right arm: xz -> -xz
constexpr double arm_inertia[6] = {0.071817287735849, 0.0957547169811321, 0.023942429245283, 0.0, 0.0414608436554153, 0.0};
constexpr double arm_spring_point[3] = {-0.235849056603774, 0.0, 0.408502548954924};  // rod midpoint, left arm frame
constexpr double slider_mass = 3.0, slider_inertia = 0.005, slider_z = 0.133974596215561;
constexpr double stiffness = 8.0e5, damping = 4.0e4, rest_length = 0.5;
constexpr double g = 9.81;
}  // namespace flyball

// Data of scenes/bench/gyroscope.yaml: a symmetric top (body frame at the mass centre, symmetry
// axis = body z) on a spherical joint at the world origin, mass centre l = 0.1 m up the axis,
// tilted by theta = pi/6 about world x, spinning in steady precession; g = 9.81 along -z.
namespace gyroscope {
constexpr double mass = 1.0, ixx = 0.002, izz = 0.004, l = 0.1, g = 9.81;
constexpr double tilt = 0.5235987755982988;                                    // about world x
constexpr double omega[3] = {0.0, -49.99999999999999, 89.16913788781845};      // world frame
}  // namespace gyroscope

// Data of scenes/bench/a04-bricard.yaml: 5 bars (1 m, 1 kg, square 0.1 m section) at rest, every
// body frame at the bar centre and parallel to the world frame; 6 revolute joints
// ground-bar1-...-bar5-ground; g = 9.81 along -y.
namespace bricard {
constexpr double axial = 0.00166666666667, transverse = 0.0841666666667;
constexpr double centre[5][3] = {{0.5, 0, 0}, {1, 0.5, 0}, {1, 1, 0.5}, {0.5, 1, 1}, {0, 0.5, 1}};
constexpr int bar_axis[5] = {0, 1, 2, 0, 1};  // the bar's long axis (x, y or z)
// joint k joins bar k (ground for k = 0) and bar k+1 (ground for k = 5)
constexpr double joint_point[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}, {0, 0, 1}};
constexpr int joint_axis[6] = {1, 2, 0, 1, 2, 0};
constexpr double g = 9.81;
}  // namespace bricard
