// Writes a result CSV of scenes/bench/chain-500.yaml with 10,000 rows for the animation
// export benchmark (bench/viewer_export.sh): a kinematically exact motion of the chain (each
// link i at angle theta_i(t) = a sin(w t + i / 25) with the mass centres following from the
// joints), so the file has the size and the column layout of a real result.
// Usage: mbd_bench_make_chain_result SCENE OUT.csv [ROWS]
#include <mbd/app/scene_sections.hpp>
#include <mbd/csv.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <cmath>
#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    mbd::declare_application_scene_sections();  // scenes/bench keep their `bench:`
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s SCENE OUT.csv [ROWS]\n", argv[0]);
        return 2;
    }
    mbd::Registry registry;
    const mbd::Model model = mbd::load_scene(argv[1], registry);
    const int rows = argc > 3 ? std::stoi(argv[3]) : 10000;
    const int n = model.body_count();
    const double link = 2.0 * model.bodies[0].position.x();  // links of equal length, the first from the origin
    mbd::CsvWriter csv(argv[2], mbd::motion_columns(model));
    mbd::State state;
    state.q.resize(model.nq());
    state.v.resize(model.nv());
    for (int r = 0; r < rows; ++r) {
        const double t = 0.001 * r;
        state.t = t;
        double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0;  // the joint at the link's start
        for (int i = 0; i < n; ++i) {
            const double theta = -0.8 * std::sin(3.0 * t + i / 25.0), omega = -2.4 * std::cos(3.0 * t + i / 25.0);
            const double c = std::cos(theta), s = std::sin(theta);
            const int q = model.q_offset(i), v = model.v_offset(i);
            state.q[q] = x + 0.5 * link * c;
            state.q[q + 1] = y + 0.5 * link * s;
            state.q[q + 2] = theta;
            state.v[v] = vx - 0.5 * link * s * omega;
            state.v[v + 1] = vy + 0.5 * link * c * omega;
            state.v[v + 2] = omega;
            x += link * c, y += link * s, vx -= link * s * omega, vy += link * c * omega;
        }
        csv.row(mbd::motion_values(model, state));
    }
    csv.close();
    std::printf("wrote %s: %d bodies, %d rows\n", argv[2], n, rows);
    return 0;
}
