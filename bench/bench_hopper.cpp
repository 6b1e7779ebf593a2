// The hopper of issue 39 in mbd (docs/benchmarks.md "The hopper against MuJoCo"): spheres and
// boxes falling through a hopper's opening into a bin (bench/hopper_scene.hpp). Writes the scene
// as OUT/hopper.yaml and as MJCF, OUT/hopper.xml, for the MuJoCo peer (mbd_peer_mujoco_hopper),
// runs mbd on it with a fixed-step integrator and reports, every 0.05 s of simulated time, the
// fraction of spheres out of the hopper, the contact pairs and the pile's height; then the time
// per simulated second, the mean contact pairs, the discharge time (90% of the spheres out),
// the final pile height, and at the state of most contacts the broad phase's share of one
// evaluation of the contact element (FCL's dynamic AABB tree refitted and traversed alone, the
// same objects, against the whole element).
//   bench_hopper OUT [SPHERES [BOXES [T_END [STEP [INTEGRATOR]]]]]   (1000 10 2 1e-4 rk4)
#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/force_couplings.hpp>
#include <mbd/simulator.hpp>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/sphere.h>

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "bench_stats.hpp"
#include "hopper_scene.hpp"

namespace {

using Clock = thread_cpu_clock;  // CPU time: the machine is shared

// The process's CPU time in seconds (every thread's, as the MuJoCo peer counts it).
double cpu_seconds() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

const mbd::ForceInstance& contact_element(const mbd::Model& model) {
    for (const mbd::ForceInstance& f : model.forces)
        if (f.type == "collision_contact") return f;
    throw std::runtime_error("the hopper has no collision element");
}

// The contact element on the bodies at `state`: its contact pairs and one evaluation's time.
class Element {
public:
    explicit Element(const mbd::Model& model) : model_(model), system_(model), f_(contact_element(model)) {}

    void at(const mbd::State& state) {
        system_.data().pose(state);
        system_.data().poses.fill(f_.bodies, state.t, view_);
    }
    int pairs() {
        std::vector<mbd::ForceCoupling> out;
        dynamic_cast<const mbd::ForceCouplings&>(*f_.force).couplings(view_, out);
        return static_cast<int>(out.size());
    }
    double seconds() {
        Eigen::VectorXd Q = Eigen::VectorXd::Zero(6 * static_cast<Eigen::Index>(f_.bodies.size()));
        return median_seconds_per_call(
            [&] {
                Q.setZero();
                f_.force->evaluate(view_, Q);
            },
            Clock());
    }

private:
    const mbd::Model& model_;
    mbd::ModelSystem system_;
    const mbd::ForceInstance& f_;
    mbd::BodyStates view_;
};

// FCL's broad phase alone over the scene's shapes (the hopper's and bin's slabs, the bodies'
// spheres and boxes; the ground plane is tested apart, as in collision_world.cpp): the objects'
// transforms and boxes set, the tree refitted and traversed, each candidate pair counted.
double broad_phase_seconds(const hopper::Spec& spec, const mbd::Model& model, const mbd::State& state, long& candidates) {
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
    std::vector<fcl::CollisionObjectd*> listed;
    for (const hopper::Slab& w : hopper::slabs(spec)) {
        objects.push_back(std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Boxd>(2 * w.hx, 2 * w.hy, 2 * w.hz)));
        objects.back()->setTranslation(Eigen::Vector3d(w.x, w.y, w.z));
        objects.back()->computeAABB();
    }
    const std::vector<hopper::Body> bodies = hopper::bodies(spec);
    for (const hopper::Body& b : bodies)
        objects.push_back(std::make_unique<fcl::CollisionObjectd>(
            b.box ? std::shared_ptr<fcl::CollisionGeometryd>(std::make_shared<fcl::Boxd>(spec.box_x, spec.box_y, spec.box_z))
                  : std::make_shared<fcl::Sphered>(spec.radius)));
    for (auto& o : objects) listed.push_back(o.get());
    fcl::DynamicAABBTreeCollisionManagerd manager;
    manager.registerObjects(listed);
    manager.setup();
    const size_t first = objects.size() - bodies.size();
    auto count = [](fcl::CollisionObjectd*, fcl::CollisionObjectd*, void* n) {
        ++*static_cast<long*>(n);
        return false;
    };
    const double seconds = median_seconds_per_call([&] {
        for (size_t k = 0; k < bodies.size(); ++k) {
            const int b = static_cast<int>(k);
            fcl::Transform3d T = fcl::Transform3d::Identity();
            T.linear() = mbd::rotation_from_euler_parameters(state.q.segment<4>(model.q_offset(b) + 3));
            T.translation() = state.q.segment<3>(model.q_offset(b));
            objects[first + k]->setTransform(T);
            objects[first + k]->computeAABB();
        }
        manager.update();
        candidates = 0;
        manager.collide(&candidates, count);
    }, Clock());
    return seconds;
}

std::vector<double> sphere_heights(const hopper::Spec& spec, const mbd::Model& model, const mbd::State& state) {
    std::vector<double> z;
    for (int b = 0; b < spec.spheres; ++b) z.push_back(state.q[model.q_offset(b) + 2]);
    return z;
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_hopper OUT [SPHERES [BOXES [T_END [STEP [INTEGRATOR]]]]]\n");
        return 2;
    }
    const std::filesystem::path out = argv[1];
    hopper::Spec spec;
    if (argc > 2) spec.spheres = std::atoi(argv[2]);
    if (argc > 3) spec.boxes = std::atoi(argv[3]);
    const double t_end = argc > 4 ? std::atof(argv[4]) : 2.0, step = argc > 5 ? std::atof(argv[5]) : 1e-4;
    const std::string integrator = argc > 6 ? argv[6] : "rk4";
    if (spec.spheres < 1 || spec.boxes < 0 || !(t_end > 0) || !(step > 0)) {
        std::fprintf(stderr, "bench_hopper: SPHERES must be at least 1, BOXES at least 0, T_END and STEP positive\n");
        return 2;
    }
    std::filesystem::create_directories(out);
    const std::string yaml = hopper::mbd_scene(spec);
    std::ofstream(out / "hopper.yaml") << yaml;
    std::ofstream(out / "hopper.xml") << hopper::mjcf(spec, step);

    mbd::Registry registry;
    const mbd::Model model = mbd::load_scene_text(yaml, (out / "hopper.yaml").string(), registry);
    mbd::SimulationSettings settings;
    settings.formulation = "augmented";
    settings.integrator = integrator;
    settings.integration.step = step;
    settings.t_end = t_end;
    settings.progress = false;
    settings.messages = mbd::MessageLog::silent();
    mbd::Simulator sim(model, registry, settings);
    Element element(model);

    const double sample = 0.01;
    double stepping = 0.0, discharge = -1.0, contacts_sum = 0.0;
    int samples = 0, most = -1;
    mbd::State busiest = sim.state();
    std::printf("%8s %10s %10s %12s %12s\n", "t [s]", "out", "pairs", "pile [m]", "cpu [s]");
    for (int k = 1; k * sample <= t_end + 1e-12; ++k) {
        const double start = cpu_seconds();
        sim.advance_to(k * sample);
        stepping += cpu_seconds() - start;
        element.at(sim.state());
        const int pairs = element.pairs();
        const hopper::Outcome o = hopper::outcome(spec, sphere_heights(spec, model, sim.state()));
        contacts_sum += pairs, ++samples;
        if (pairs > most) most = pairs, busiest = sim.state();
        if (discharge < 0 && o.out_fraction >= 0.9) discharge = sim.time();
        if (k % 5 == 0) std::printf("%8.2f %10.3f %10d %12.4f %12.1f\n", sim.time(), o.out_fraction, pairs, o.pile_height, stepping);
        std::fflush(stdout);
    }
    const hopper::Outcome end = hopper::outcome(spec, sphere_heights(spec, model, sim.state()));
    element.at(busiest);
    long candidates = 0;
    const double whole = element.seconds(), broad = broad_phase_seconds(spec, model, busiest, candidates);
    std::printf("mbd %s h = %g, %d spheres + %d boxes, %.2f s simulated: %.1f CPU s per simulated second, %ld steps\n",
                integrator.c_str(), step, spec.spheres, spec.boxes, sim.time(), stepping / sim.time(), sim.stats().steps);
    std::printf("contact pairs: mean %.0f, most %d; discharge (90%% out) %s; pile height %.4f m, out %.3f\n",
                contacts_sum / samples, most, discharge < 0 ? "not reached" : (std::to_string(discharge) + " s").c_str(),
                end.pile_height, end.out_fraction);
    std::printf("at the most contacts (t = %.2f s): element %.1f us, broad phase %.1f us of CPU (%.0f%%, %ld candidate pairs)\n",
                busiest.t, 1e6 * whole, 1e6 * broad, 100 * broad / whole, candidates);
    return 0;
} catch (const std::exception& e) {  // a bad integrator name, a failed step: said, not an abort
    std::fprintf(stderr, "bench_hopper: %s\n", e.what());
    return 1;
}
