// MuJoCo on the hopper of issue 39 (docs/benchmarks.md "The hopper against MuJoCo"): the MJCF
// bench_hopper writes (bench/hopper_scene.hpp, same bodies as the mbd scene), stepped with the
// file's integrator and step, reporting what bench_hopper reports for mbd: every 0.05 s the
// fraction of spheres out of the hopper, the contacts (ncon) and the pile's height; then the time
// per simulated second, the mean contacts, the discharge time (90% of the spheres out), the
// final pile height and collision detection's share of the step (MuJoCo 2.2's timers do not
// split its broad and narrow phases).
//   mbd_peer_mujoco_hopper HOPPER.xml [T_END]   (2)
#include <mujoco/mujoco.h>

#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../hopper_scene.hpp"

namespace {

// The process's CPU time in seconds (the machine is shared: the wall clock measures the scheduler).
double cpu_seconds() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

mjtNum now_us() { return 1e6 * cpu_seconds(); }

double numeric(const mjModel* m, const char* name) {
    const int id = mj_name2id(m, mjOBJ_NUMERIC, name);
    if (id < 0) {
        std::fprintf(stderr, "the model has no numeric '%s': not written by bench_hopper\n", name);
        std::exit(2);
    }
    return m->numeric_data[m->numeric_adr[id]];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: mbd_peer_mujoco_hopper HOPPER.xml [T_END]\n");
        return 2;
    }
    const double t_end = argc > 2 ? std::atof(argv[2]) : 2.0;
    if (!(t_end > 0)) {
        std::fprintf(stderr, "mbd_peer_mujoco_hopper: T_END must be positive\n");
        return 2;
    }
    char error[1000] = "";
    mjModel* m = mj_loadXML(argv[1], nullptr, error, sizeof error);
    if (!m) {
        std::fprintf(stderr, "%s: %s\n", argv[1], error);
        return 2;
    }
    hopper::Spec spec;  // the outcome's geometry, from the file
    spec.floor_z = numeric(m, "hopper_floor");
    spec.radius = numeric(m, "radius");
    spec.wall = numeric(m, "wall");
    std::vector<int> spheres;  // bodies s0, s1, ...
    for (int b = 0; b < m->nbody; ++b)
        if (const char* name = mj_id2name(m, mjOBJ_BODY, b); name && name[0] == 's') spheres.push_back(b);
    mjcb_time = now_us;
    mjData* d = mj_makeData(m);
    mj_forward(m, d);
    const double sample = 0.01;
    const int per_sample = static_cast<int>(std::lround(sample / m->opt.timestep));
    double stepping = 0.0, discharge = -1.0, contacts_sum = 0.0;
    long steps = 0;
    int samples = 0, most = 0;
    hopper::Outcome o;
    std::printf("%8s %10s %10s %12s %12s\n", "t [s]", "out", "ncon", "pile [m]", "cpu [s]");
    for (int k = 1; k * sample <= t_end + 1e-12; ++k) {
        for (int s = 0; s < per_sample; ++s) {
            const double start = cpu_seconds();
            mj_step(m, d);
            stepping += cpu_seconds() - start;
            contacts_sum += d->ncon, ++samples, ++steps;
            most = std::max(most, d->ncon);
            for (int w = 0; w < mjNWARNING; ++w)
                if (d->warning[w].number > 0) {
                    std::fprintf(stderr, "MuJoCo warning %d at t = %g (e.g. too many contacts): the run is void\n", w, d->time);
                    return 1;
                }
        }
        std::vector<double> z;
        for (int b : spheres) z.push_back(d->xpos[3 * b + 2]);
        o = hopper::outcome(spec, z);
        if (discharge < 0 && o.out_fraction >= 0.9) discharge = d->time;
        if (k % 5 == 0) std::printf("%8.2f %10.3f %10d %12.4f %12.1f\n", d->time, o.out_fraction, d->ncon, o.pile_height, stepping);
        std::fflush(stdout);
    }
    std::printf("mujoco %s h = %g, %zu spheres, %.2f s simulated: %.1f CPU s per simulated second, %ld steps\n",
                m->opt.integrator == mjINT_EULER ? "Euler" : "RK4", m->opt.timestep, spheres.size(), d->time,
                stepping / d->time, steps);
    std::printf("contacts: mean %.0f, most %d; discharge (90%% out) %s; pile height %.4f m, out %.3f\n",
                contacts_sum / samples, most, discharge < 0 ? "not reached" : (std::to_string(discharge) + " s").c_str(),
                o.pile_height, o.out_fraction);
    // the timers accumulate from the start
    std::printf("collision detection (broad and narrow phase): %.0f%% of the step time\n",
                100 * d->timer[mjTIMER_POS_COLLISION].duration / d->timer[mjTIMER_STEP].duration);
    mj_deleteData(d);
    mj_deleteModel(m);
    return 0;
}
