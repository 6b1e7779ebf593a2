// Cost of the collision contact element (plugins/forces/collision_contact) against the number
// of bodies (issue 39, docs/benchmarks.md): N spheres (r = 0.05 m, 0.1 kg) on a square grid on a
// ground plane, each pressed 1 mm into it, either apart (spacing 0.12 m: N contacts) or each
// pressed 1 mm into its grid neighbours too (spacing 0.098 m: about 3N contacts), or lifted
// 1 cm off the ground and apart (no contact: the cost of the tree's refit and traversal and the
// sphere/plane tests). Median time of one evaluation, and of the augmented formulation's whole
// rhs, and the time of one force Jacobian (sparse, one contact at a time: System::force_jacobians),
// with the slope of log(time) against log(N). Times are the thread's CPU time (thread_cpu_clock):
// the machine is shared. The pairs grow as N^2 / 2; a cost that grows
// with the contacts and bodies has slope 1 (N log N for the tree: slightly above).
//   bench_collision [N...]   (default 100 300 1000 3000 10000)
#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "augmented_rhs.hpp"
#include "bench_stats.hpp"

namespace {

std::string grid_scene(int count, double spacing, double height) {
    const int side = static_cast<int>(std::ceil(std::sqrt(count)));
    std::ostringstream s;
    s.precision(17);
    s << "dimension: spatial\ngravity: [0, 0, -9.81]\nground:\n  collision:\n"
         "    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 0.5}}\nbodies:\n";
    for (int b = 0; b < count; ++b)
        s << "  - name: s" << b << "\n    mass: 0.1\n    inertia: [1e-4, 1e-4, 1e-4]\n    position: ["
          << spacing * (b % side) << ", " << spacing * (b / side) << ", " << height << "]\n"
          << "    collision:\n      - {shape: sphere, radius: 0.05, material: {stiffness: 1e6, restitution: 0.5, "
             "impact_velocity: 1, static_friction: 0.5, kinetic_friction: 0.4, stiction_velocity: 1e-3}}\n";
    return s.str();
}

struct Timing {
    double element = 0.0, rhs = 0.0, jacobian = 0.0;
};

// One force Jacobian after one warm-up (a median would repeat it: seconds at 10,000 bodies).
double jacobian_seconds(mbd::ModelSystem& system, const mbd::State& state) {
    Eigen::SparseMatrix<double> dq, dv;
    system.force_jacobians(state, dq, dv);
    const auto start = thread_cpu_clock::now();
    system.force_jacobians(state, dq, dv);
    return std::chrono::duration<double>(thread_cpu_clock::now() - start).count();
}

Timing time_scene(mbd::Registry& registry, const std::string& yaml) {
    const mbd::Model model = mbd::load_scene_text(yaml, "bench.yaml", registry);
    mbd::ModelSystem system(model);
    mbd::State state = system.initial_state();
    Timing t;
    if (!std::getenv("BENCH_COLLISION_ELEMENT_ONLY")) t.rhs = augmented_rhs_seconds(registry, system, state);
    t.jacobian = jacobian_seconds(system, state);
    // the element alone, on the bodies' initial states
    const mbd::ForceInstance* contact = nullptr;
    for (const auto& force : model.forces)
        if (force.type == "collision_contact") contact = &force;
    std::vector<mbd::SpatialBody> bodies(contact->bodies.size());
    mbd::BodyStates view;
    for (size_t k = 0; k < bodies.size(); ++k) {
        const int b = contact->bodies[k];
        if (b < 0) bodies[k].ground = true;
        else bodies[k].set(state.q.segment<3>(7 * b), state.q.segment<4>(7 * b + 3), state.v.segment<3>(6 * b),
                           state.v.segment<3>(6 * b + 3));
        view.spatial_bodies.push_back(&bodies[k]);
    }
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(6 * static_cast<Eigen::Index>(bodies.size()));
    t.element = median_seconds_per_call(
        [&] {
            Q.setZero();
            contact->force->evaluate(view, Q);
        },
        thread_cpu_clock());
    return t;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> counts = {100, 300, 1000, 3000, 10000};
    if (argc > 1) {
        counts.clear();
        for (int k = 1; k < argc; ++k) counts.push_back(std::atoi(argv[k]));
    }
    mbd::Registry registry;
    struct Layout {
        const char* name;
        double spacing, height;
    };
    const Layout layouts[] = {{"apart (N contacts)", 0.12, 0.049}, {"touching (~3N contacts)", 0.098, 0.049},
                              {"lifted (no contact)", 0.12, 0.06}};
    std::printf("%-24s %7s %14s %12s %14s %14s\n", "layout", "N", "element [us]", "per body", "rhs [us]",
                "jacobian [ms]");
    for (const Layout& layout : layouts) {
        std::vector<double> n, te, tr, tj;
        for (int count : counts) {
            const Timing t = time_scene(registry, grid_scene(count, layout.spacing, layout.height));
            std::printf("%-24s %7d %14.1f %12.3f %14.1f %14.2f\n", layout.name, count, 1e6 * t.element,
                        1e6 * t.element / count, 1e6 * t.rhs, 1e3 * t.jacobian);
            std::fflush(stdout);
            n.push_back(count), te.push_back(t.element), tj.push_back(t.jacobian);
            if (t.rhs > 0) tr.push_back(t.rhs);
        }
        std::printf("%-24s slope of log(time) against log(N): element %.3f", layout.name, slope(n, te));
        if (tr.size() > 1) std::printf(", rhs %.3f", slope(n, tr));
        std::printf(", jacobian %.3f", slope(n, tj));
        std::printf("\n");
    }
    return 0;
}
