// MuJoCo peer of the work-precision benchmark (bench/peers/peer_common.hpp): the benchmark
// models written in MJCF (generalized coordinates, hinge joints; loop closures are MuJoCo's
// soft `connect` equality constraints, made as stiff as the step allows) and integrated with
// MuJoCo's fixed-step integrators (rk4: RK4, euler: semi-implicit Euler) at the given step
// (shortened so that the output step is a whole number of steps). Contacts are disabled.
#include "peer_common.hpp"

#include <mujoco/mujoco.h>

#include <ctime>
#include <fstream>
#include <sstream>
#include <unistd.h>

int main(int argc, char** argv) {
    const PeerArgs a = parse_peer_args(argc, argv);
    if (a.tolerance) {
        std::fprintf(stderr, "mujoco peer: only fixed steps (step VALUE)\n");
        return 2;
    }
    const long per_output = std::max(1L, static_cast<long>(std::ceil(a.output_step / a.value - 1e-9)));
    const double h = a.output_step / per_output;
    const std::string integrator = a.integrator == "euler" ? "Euler" : "RK4";
    std::ostringstream x;
    char opt[256];
    std::snprintf(opt, sizeof opt, "<option timestep=\"%.17g\" integrator=\"%s\" gravity=\"0 -9.81 0\" tolerance=\"1e-14\" iterations=\"200\">",
                  h, integrator.c_str());
    x << "<mujoco>" << opt << "<flag contact=\"disable\" refsafe=\"disable\"/></option><worldbody>";
    std::vector<std::pair<std::string, int>> qvel;  // initial joint rates, in joint order
    std::vector<std::string> measured_bodies;  // measured point: (measured_x, 0, 0) in each body frame
    double measured_x = 0.0;
    if (a.model == "pendulum_a01") {
        x << "<body name=\"bob\"><joint type=\"hinge\" axis=\"0 0 1\"/>"
             "<inertial pos=\"1 0 0\" mass=\"1\" diaginertia=\"1e-6 1e-6 1e-6\"/></body>";
        measured_bodies = {"bob"};
        measured_x = 1.0;
    } else if (a.model == "four_bar_2") {
        const int n = 2;
        const char* rod = "<inertial pos=\"0.5 0 0\" mass=\"1\" diaginertia=\"1e-6 0.0833333333333333 0.0833333333333333\"/>";
        for (int i = 0; i <= n; ++i) {
            x << "<body name=\"crank" << i << "\" pos=\"" << i << " 0 0\" euler=\"0 0 90\">"
              << "<joint type=\"hinge\" axis=\"0 0 1\"/>" << rod;
            if (i < n)
                x << "<body name=\"coupler" << i << "\" pos=\"1 0 0\" euler=\"0 0 -90\">"
                  << "<joint type=\"hinge\" axis=\"0 0 1\"/>" << rod << "</body>";
            x << "</body>";
        }
        x << "</worldbody><equality>";
        for (int k = 0; k < n; ++k)
            x << "<connect body1=\"coupler" << k << "\" body2=\"crank" << k + 1
              << "\" anchor=\"1 0 0\" solref=\"" << 2 * h << " 1\" solimp=\"0.9999 0.9999 0.001\"/>";
        x << "</equality><worldbody>";
        // joint order: crank0, coupler0, crank1, coupler1, crank2
        measured_bodies = {"crank0"};
        measured_x = 1.0;
    } else if (const int n = chain_links(a.model)) {
        for (int k = 0; k < n; ++k)
            x << "<body name=\"l" << k << "\" pos=\"" << (k == 0 ? 0.0 : 0.1) << " 0 0\">"
              << "<joint type=\"hinge\" axis=\"0 0 1\"/>"
              << "<inertial pos=\"0.05 0 0\" mass=\"1\" diaginertia=\"1e-9 0.000833333333333333 0.000833333333333333\"/>";
        for (int k = 0; k < n; ++k) x << "</body>";
        for (int k : chain_measured(n)) measured_bodies.push_back("l" + std::to_string(k));
        measured_x = 0.1;
    } else {
        std::fprintf(stderr, "mujoco peer: unknown model '%s'\n", a.model.c_str());
        return 2;
    }
    x << "</worldbody></mujoco>";

    char path[] = "/tmp/mbd_peer_mujoco_XXXXXX.xml";
    const int fd = ::mkstemps(path, 4);
    if (fd < 0) return 1;
    {
        const std::string text = x.str();
        if (::write(fd, text.data(), text.size()) != static_cast<ssize_t>(text.size())) return 1;
        ::close(fd);
    }
    char error[1000] = "";
    mjModel* m = mj_loadXML(path, nullptr, error, sizeof error);
    ::unlink(path);
    if (!m) {
        std::fprintf(stderr, "mujoco peer: %s\n", error);
        return 1;
    }
    mjData* d = mj_makeData(m);
    if (a.model == "four_bar_2") {
        const double rates[] = {-1, 1, -1, 1, -1};
        for (int j = 0; j < m->nv && j < 5; ++j) d->qvel[j] = rates[j];
    }
    std::vector<int> bodies;
    for (const auto& name : measured_bodies) bodies.push_back(mj_name2id(m, mjOBJ_BODY, name.c_str()));
    const std::vector<double> times = peer_output_times(a);
    std::vector<std::vector<double>> rows;
    long steps = 0;
    const std::clock_t start = std::clock();
    for (double t : times) {
        const long target = std::lround(t / h);
        while (steps < target) {
            mj_step(m, d);
            ++steps;
        }
        mj_kinematics(m, d);
        std::vector<double> row{t};
        for (int body : bodies) {
            const double* p = d->xpos + 3 * body;
            const double* R = d->xmat + 9 * body;
            row.insert(row.end(), {p[0] + R[0] * measured_x, p[1] + R[3] * measured_x, p[2] + R[6] * measured_x});
        }
        rows.push_back(row);
    }
    const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    std::printf("%.9g %ld\n", cpu, steps);
    for (const auto& row : rows) {
        for (size_t k = 0; k < row.size(); ++k) std::printf(k ? " %.17g" : "%.17g", row[k]);
        std::printf("\n");
    }
    mj_deleteData(d);
    mj_deleteModel(m);
    return 0;
}
