// Simbody peer of the work-precision benchmark (bench/peers/peer_common.hpp): the benchmark
// models built with Simbody's own API (internal coordinates, Pin mobilizers, Ball loop
// closures) and integrated with its error-controlled integrators (rkmerson: RungeKuttaMerson,
// rk3: RungeKutta3, cpodes: CPodes BDF) at the given accuracy.
#include "peer_common.hpp"

#include <Simbody.h>

#include <ctime>
#include <memory>

using namespace SimTK;

int main(int argc, char** argv) {
    const PeerArgs a = parse_peer_args(argc, argv);
    if (!a.tolerance) {
        std::fprintf(stderr, "simbody peer: only error-controlled integrators (tol VALUE)\n");
        return 2;
    }
    try {
        MultibodySystem system;
        SimbodyMatterSubsystem matter(system);
        GeneralForceSubsystem forces(system);
        Force::UniformGravity gravity(forces, matter, Vec3(0, -9.81, 0));
        std::vector<std::pair<MobilizedBody, Vec3>> measured;
        std::vector<std::pair<MobilizedBody, Real>> rates;  // initial u of each mobilizer
        if (a.model == "pendulum_a01") {
            // point mass 1 kg at the body origin with the scene's tiny inertia 1e-6, pivot 1 m away
            Body::Rigid bob(MassProperties(1.0, Vec3(0), Inertia(1e-6)));
            MobilizedBody::Pin pin(matter.Ground(), Transform(Vec3(0)), bob, Transform(Vec3(-1, 0, 0)));
            measured.push_back({pin, Vec3(0)});
        } else if (a.model == "four_bar_2") {
            const int n = 2;
            // rods of 1 m, 1 kg along body x, frame at one end, Izz = m L^2 / 12 about the centre
            const MassProperties rod(1.0, Vec3(0.5, 0, 0),
                                     Inertia(Vec3(1e-6, 1.0 / 12, 1.0 / 12)).shiftFromMassCenter(Vec3(0.5, 0, 0), 1.0));
            Body::Rigid body(rod);
            std::vector<MobilizedBody::Pin> cranks, couplers;
            for (int i = 0; i <= n; ++i) {
                cranks.emplace_back(matter.Ground(), Transform(Rotation(Pi / 2, ZAxis), Vec3(i, 0, 0)), body,
                                    Transform());
                rates.push_back({cranks.back(), -1.0});
            }
            for (int k = 0; k < n; ++k) {
                couplers.emplace_back(cranks[k], Transform(Rotation(-Pi / 2, ZAxis), Vec3(1, 0, 0)), body, Transform());
                rates.push_back({couplers.back(), 1.0});
                Constraint::Ball(couplers[k], Vec3(1, 0, 0), cranks[k + 1], Vec3(1, 0, 0));
            }
            measured.push_back({cranks[0], Vec3(1, 0, 0)});
        } else if (const int n = chain_links(a.model)) {
            const double L = 0.1;
            const MassProperties link(1.0, Vec3(L / 2, 0, 0),
                                      Inertia(Vec3(1e-9, L * L / 12, L * L / 12)).shiftFromMassCenter(Vec3(L / 2, 0, 0), 1.0));
            Body::Rigid body(link);
            MobilizedBody parent = matter.Ground();
            std::vector<MobilizedBody> links;
            for (int k = 0; k < n; ++k) {
                MobilizedBody::Pin pin(parent, Transform(Vec3(k == 0 ? 0.0 : L, 0, 0)), body, Transform());
                parent = pin;
                links.push_back(pin);
            }
            for (int k : chain_measured(n)) measured.push_back({links[k], Vec3(L, 0, 0)});
        } else {
            std::fprintf(stderr, "simbody peer: unknown model '%s'\n", a.model.c_str());
            return 2;
        }
        system.realizeTopology();
        State state = system.getDefaultState();
        for (auto& [mb, u] : rates) mb.setOneU(state, 0, u);
        system.realize(state, Stage::Position);
        system.projectU(state, 1e-12);

        std::unique_ptr<Integrator> integ;
        if (a.integrator == "rk3") integ = std::make_unique<RungeKutta3Integrator>(system);
        else if (a.integrator == "cpodes") integ = std::make_unique<CPodesIntegrator>(system);
        else integ = std::make_unique<RungeKuttaMersonIntegrator>(system);
        integ->setAccuracy(a.value);
        integ->setConstraintTolerance(std::min(1e-3, a.value));
        std::vector<double> times = peer_output_times(a);
        std::vector<std::vector<double>> rows;
        const std::clock_t start = std::clock();
        integ->initialize(state);
        for (double t : times) {
            // the first call reports the start of the continuous interval without advancing
            while (integ->getTime() < t - 1e-12) {
                const Integrator::SuccessfulStepStatus status = integ->stepTo(t);
                if (status == Integrator::EndOfSimulation) throw std::runtime_error("integration ended early");
            }
            const State& s = integ->getState();
            std::vector<double> row{t};
            for (auto& [mb, p] : measured) {
                const Vec3 r = mb.findStationLocationInGround(s, p);
                row.insert(row.end(), {r[0], r[1], r[2]});
            }
            rows.push_back(row);
        }
        const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
        std::printf("%.9g %d\n", cpu, integ->getNumStepsTaken());
        for (const auto& row : rows) {
            for (size_t k = 0; k < row.size(); ++k) std::printf(k ? " %.17g" : "%.17g", row[k]);
            std::printf("\n");
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "simbody peer: %s\n", e.what());
        return 1;
    }
    return 0;
}
