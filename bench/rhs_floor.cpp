// A floor for the cost of one right-hand side (issue 13): the articulated-body algorithm
// written by hand for one mechanism only, a planar chain of N equal links hanging from the
// ground by pins (scenes/bench/chain-N.yaml: length L, mass m, inertia m L^2 / 12, gravity
// -g along y). Relative joint angles s and speeds u in, joint accelerations out, in
// world-frame planar spatial vectors (vx, vy, omega) at each link's centre of mass; no
// allocation, no indirection, no generality. mbd's own rhs on the same scene (the embedding
// formulation's recursive path, which `mbd simulate` takes on a tree) is timed next to it
// at the same state, and both accelerations are compared first: a floor that computed
// something else would not be one.
//   rhs_floor [scenes/bench/chain-5.yaml]
#include <mbd/app/scene_sections.hpp>
#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "bench_stats.hpp"

namespace {

struct PinChain {
    int n;
    double length, mass, inertia, gravity;
};

// Joint accelerations of the pin chain (Featherstone's articulated-body algorithm in the
// plane; the transfer from parent to child centre of mass is [I2, k x d; 0, 1]).
class PinChainFloor {
public:
    explicit PinChainFloor(const PinChain& chain) : c_(chain), links_(chain.n) {}

    void accelerations(const double* s, const double* u, double* udot) {
        const double half = 0.5 * c_.length;
        double phi = 0.0, w = 0.0, ox = 0.0, oy = 0.0, px = 0.0, py = 0.0, wp = 0.0;
        for (int i = 0; i < c_.n; ++i) {  // kinematics, root to tip
            Link& k = links_[i];
            phi += s[i];
            w += u[i];
            const double cx = std::cos(phi), sy = std::sin(phi);
            const double rx = half * cx, ry = half * sy;  // joint -> centre of mass
            const double x = ox + rx, y = oy + ry;
            k.dx = x - px, k.dy = y - py;                  // parent's centre -> this centre
            k.h[0] = -ry, k.h[1] = rx, k.h[2] = 1.0;
            // velocity-product term: -wp^2 (joint - parent centre) - w^2 (centre - joint)
            k.a[0] = -wp * wp * (ox - px) - w * w * rx;
            k.a[1] = -wp * wp * (oy - py) - w * w * ry;
            k.a[2] = 0.0;
            k.P.setZero();
            k.P(0, 0) = k.P(1, 1) = c_.mass;
            k.P(2, 2) = c_.inertia;
            k.z = Eigen::Vector3d(0.0, c_.mass * c_.gravity, 0.0);  // -Q
            ox += 2.0 * rx, oy += 2.0 * ry;
            px = x, py = y, wp = w;
        }
        for (int i = c_.n - 1; i >= 0; --i) {  // articulated inertias, tip to root
            Link& k = links_[i];
            k.U = k.P * k.h;
            k.D = k.h.dot(k.U);
            if (i == 0) break;
            const Eigen::Matrix3d Pa = k.P - k.U * k.U.transpose() / k.D;
            const Eigen::Vector3d za = Pa * k.a + k.z - k.U * (k.h.dot(k.z) / k.D);
            Link& p = links_[i - 1];
            const Eigen::Vector2d d(-k.dy, k.dx);  // Phi = [I2 d; 0 1]
            const Eigen::Vector2d y12 = Pa.topLeftCorner<2, 2>() * d + Pa.topRightCorner<2, 1>();
            p.P.topLeftCorner<2, 2>() += Pa.topLeftCorner<2, 2>();
            p.P.topRightCorner<2, 1>() += y12;
            p.P.bottomLeftCorner<1, 2>() += y12.transpose();
            p.P(2, 2) += d.dot(y12) + Pa.bottomLeftCorner<1, 2>().dot(d) + Pa(2, 2);
            p.z.head<2>() += za.head<2>();
            p.z[2] += d.dot(za.head<2>()) + za[2];
        }
        Eigen::Vector3d vdot = Eigen::Vector3d::Zero();
        for (int i = 0; i < c_.n; ++i) {  // accelerations, root to tip
            const Link& k = links_[i];
            const Eigen::Vector3d base(vdot[0] - k.dy * vdot[2] + k.a[0], vdot[1] + k.dx * vdot[2] + k.a[1], vdot[2]);
            udot[i] = -(k.U.dot(base) + k.h.dot(k.z)) / k.D;
            vdot = base + k.h * udot[i];
        }
    }

private:
    struct Link {
        double dx = 0, dy = 0, D = 0;
        Eigen::Vector3d h, a, z, U;
        Eigen::Matrix3d P;
    };
    PinChain c_;
    std::vector<Link> links_;
};

}  // namespace

int main(int argc, char** argv) {
    mbd::declare_application_scene_sections();  // scenes/bench keep their `bench:`
    const std::string path = argc > 1 ? argv[1] : "scenes/bench/chain-5.yaml";
    try {
        mbd::Registry registry;
        const mbd::Model model = mbd::load_scene(path, registry);
        mbd::ModelSystem system(model);
        const int n = system.body_count();
        // the chain's data, read from the scene (the floor trusts it to be a pin chain)
        const double length = 2.0 * system.initial_state().q[0];
        const PinChain chain{n, length, system.mass_matrix().coeff(0, 0), system.mass_matrix().coeff(2, 2), 9.81};

        mbd::Param node;
        node.kind = mbd::Param::Kind::Map;
        mbd::FormulationSpec spec{"embedding", "embedding", mbd::Params("formulation 'embedding'", &node)};
        auto formulation = registry.create_formulation(spec, "bench");
        mbd::FormulationOptions options;
        options.sparse_threshold = 30;  // as mbd simulate
        options.log = mbd::MessageLog([](const std::string& line) { std::printf("%s\n", line.c_str()); });
        formulation->bind(system, options);
        if (formulation->ode_size() != 2 * n) throw std::runtime_error("expected the recursive path: 2 N states");

        // a state with every joint bent and turning, so that the velocity terms count
        Eigen::VectorXd y(2 * n), ydot;
        for (int i = 0; i < n; ++i) {
            y[i] = 0.3 - 0.17 * i;
            y[n + i] = 0.9 - 0.4 * i;
        }
        PinChainFloor floor(chain);
        Eigen::VectorXd udot(n);
        floor.accelerations(y.data(), y.data() + n, udot.data());
        formulation->rhs(0.0, y, ydot);
        const double gap = (ydot.tail(n) - udot).lpNorm<Eigen::Infinity>() / udot.lpNorm<Eigen::Infinity>();
        std::printf("joint accelerations, relative difference mbd vs floor: %.2e\n", gap);
        if (!(gap < 1e-12)) throw std::runtime_error("the floor and mbd disagree: not the same mechanism");

        const double t_floor = median_seconds_per_call([&] { floor.accelerations(y.data(), y.data() + n, udot.data()); });
        const double t_mbd = median_seconds_per_call([&] { formulation->rhs(0.0, y, ydot); });
        std::printf("%-28s %10s\n", ("rhs of the " + std::to_string(n) + "-link chain").c_str(), "[us]");
        std::printf("%-28s %10.3f\n", "floor (hand-written ABA)", 1e6 * t_floor);
        std::printf("%-28s %10.3f\n", "mbd embedding (recursive)", 1e6 * t_mbd);
        std::printf("%-28s %10.2f\n", "mbd / floor", t_mbd / t_floor);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rhs_floor: %s\n", e.what());
        return 1;
    }
    return 0;
}
