// Simbody peer of the work-precision benchmark (bench/peers/peer_common.hpp): the benchmark
// models built with Simbody's own API (internal coordinates: Pin, Slider and Ball mobilizers;
// loop closures as Simbody constraints; drivers as prescribed Motions) and integrated with its
// error-controlled integrators (rkmerson: RungeKuttaMerson, rk3: RungeKutta3, cpodes: CPodes
// BDF) at the given accuracy.
#include "peer_common.hpp"

#include <Simbody.h>

#include <ctime>
#include <functional>
#include <memory>

using namespace SimTK;

namespace {

// A model: what to measure (a station of a body, in the body frame) and how to set the initial
// state beyond the mobilizers' default (zero) coordinates.
struct Model {
    std::vector<std::pair<MobilizedBody, Vec3>> measured;
    std::vector<std::function<void(State&)>> set_q;  // initial positions (before realize(Position))
    std::vector<std::function<void(State&)>> set_u;  // initial velocities
    double constraint_tolerance = 0;  // > 0: constraint tolerance = this x accuracy (else min(1e-3, accuracy))
    void rate(const MobilizedBody& mb, Real u) {
        set_u.push_back([mb, u](State& s) { mb.setOneU(s, 0, u); });
    }
};

// A rotation whose z axis (Pin) or x axis (Slider) is the given world axis; used for both
// mobilizer frames F and M, so that q = 0 is the scene's initial configuration.
Rotation axis_frame(const Vec3& axis, CoordinateAxis along) { return Rotation(UnitVec3(axis), along); }

Vec3 unit(int k) {
    Vec3 e(0);
    e[k] = 1;
    return e;
}

// IFToMM A01: point mass 1 kg (tiny inertia 1e-6 as in the scene) 1 m from the pivot.
Model build_pendulum(SimbodyMatterSubsystem& matter, GeneralForceSubsystem& forces) {
    Force::UniformGravity(forces, matter, Vec3(0, -9.81, 0));
    Model m;
    Body::Rigid bob(MassProperties(1.0, Vec3(0), Inertia(1e-6)));
    MobilizedBody::Pin pin(matter.Ground(), Transform(Vec3(0)), bob, Transform(Vec3(-1, 0, 0)));
    m.measured.push_back({pin, Vec3(0)});
    return m;
}

// IFToMM A02 with n loops: n+1 cranks pinned to the ground at x = 0..n, n couplers pinned to
// crank k and closed on crank k+1 by a Ball constraint (its z rows are redundant with the
// planar tree; Simbody solves them in the least-squares sense). Rods of 1 m, 1 kg along body x,
// frame at one end, Izz = m L^2 / 12 about the centre. Start: cranks up, tip B0 at 1 m/s along
// +x (crank rate -1), couplers translating (relative rate +1). Measured: the tip of crank 0.
Model build_four_bar(SimbodyMatterSubsystem& matter, GeneralForceSubsystem& forces, int n) {
    Force::UniformGravity(forces, matter, Vec3(0, -9.81, 0));
    Model m;
    const MassProperties rod(1.0, Vec3(0.5, 0, 0),
                             Inertia(Vec3(1e-6, 1.0 / 12, 1.0 / 12)).shiftFromMassCenter(Vec3(0.5, 0, 0), 1.0));
    Body::Rigid body(rod);
    std::vector<MobilizedBody::Pin> cranks;
    for (int i = 0; i <= n; ++i) {
        cranks.emplace_back(matter.Ground(), Transform(Rotation(Pi / 2, ZAxis), Vec3(i, 0, 0)), body, Transform());
        m.rate(cranks.back(), -1.0);
    }
    for (int k = 0; k < n; ++k) {
        MobilizedBody::Pin coupler(cranks[k], Transform(Rotation(-Pi / 2, ZAxis), Vec3(1, 0, 0)), body, Transform());
        m.rate(coupler, 1.0);
        Constraint::Ball(coupler, Vec3(1, 0, 0), cranks[k + 1], Vec3(1, 0, 0));
    }
    m.measured.push_back({cranks[0], Vec3(1, 0, 0)});
    return m;
}

// Planar chain of n links (0.1 m, 1 kg, I = m L^2 / 12), released at rest horizontally.
Model build_chain(SimbodyMatterSubsystem& matter, GeneralForceSubsystem& forces, int n) {
    Force::UniformGravity(forces, matter, Vec3(0, -9.81, 0));
    Model m;
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
    for (int k : chain_measured(n)) m.measured.push_back({links[k], Vec3(L, 0, 0)});
    return m;
}

// Heavy symmetric top on a Ball mobilizer at the world origin (body frame at the mass centre,
// the pivot at -l along body z), tilted pi/6 about x, with the scene's angular velocity.
Model build_gyroscope(SimbodyMatterSubsystem& matter, GeneralForceSubsystem& forces) {
    using namespace gyroscope;
    Force::UniformGravity(forces, matter, Vec3(0, 0, -g));
    Model m;
    Body::Rigid top(MassProperties(mass, Vec3(0), Inertia(ixx, ixx, izz)));
    MobilizedBody::Ball ball(matter.Ground(), Transform(), top, Transform(Vec3(0, 0, -l)));
    m.set_q.push_back([ball](State& s) { ball.setQToFitRotation(s, Rotation(tilt, XAxis)); });
    // the Ball's u is w_FM in F = ground
    m.set_u.push_back([ball](State& s) { ball.setUToFitAngularVelocity(s, Vec3(omega[0], omega[1], omega[2])); });
    m.measured.push_back({ball, Vec3(0)});
    return m;
}

// IFToMM A04 Bricard linkage: a Pin tree ground-bar1-...-bar5; the sixth revolute joint
// (bar5-ground at (0, 0, 1), axis x) closes the loop as a Ball constraint plus two
// ConstantAngle (perpendicularity) constraints keeping bar5's x axis normal to world y and z.
// The 5 closure rows on a 5-DOF tree leave the 1-DOF mechanism only because one row is
// redundant (Simbody's constraint solver handles the rank deficiency). Measured: corner J3.
Model build_bricard(SimbodyMatterSubsystem& matter, GeneralForceSubsystem& forces) {
    using namespace bricard;
    Force::UniformGravity(forces, matter, Vec3(0, -g, 0));
    Model m;
    MobilizedBody parent = matter.Ground();
    Vec3 parent_origin(0);
    std::vector<MobilizedBody> bars;
    for (int k = 0; k < 5; ++k) {
        const Vec3 c(centre[k][0], centre[k][1], centre[k][2]);
        Vec3 inertia(transverse);
        inertia[bar_axis[k]] = axial;
        Body::Rigid body(MassProperties(1.0, Vec3(0), Inertia(inertia)));
        const Vec3 p(joint_point[k][0], joint_point[k][1], joint_point[k][2]);
        const Rotation R = axis_frame(unit(joint_axis[k]), ZAxis);
        MobilizedBody::Pin pin(parent, Transform(R, p - parent_origin), body, Transform(R, p - c));
        bars.push_back(pin);
        parent = pin;
        parent_origin = c;
    }
    const Vec3 p5(joint_point[5][0], joint_point[5][1], joint_point[5][2]);
    Constraint::Ball(matter.Ground(), p5, bars[4], p5 - parent_origin);
    const UnitVec3 axis5(unit(joint_axis[5]));
    Constraint::ConstantAngle(matter.Ground(), UnitVec3(unit((joint_axis[5] + 1) % 3)), bars[4], axis5);
    Constraint::ConstantAngle(matter.Ground(), UnitVec3(unit((joint_axis[5] + 2) % 3)), bars[4], axis5);
    const Vec3 c3(centre[2][0], centre[2][1], centre[2][2]);
    m.measured.push_back({bars[2], Vec3(joint_point[3][0], joint_point[3][1], joint_point[3][2]) - c3});
    // with the constraint tolerance at the accuracy, Simbody's local projection of this
    // rank-deficient closure diverges (projectQ: "locally diverged") within a few steps
    m.constraint_tolerance = 1e-2;
    return m;
}

// IFToMM A05 flyball governor: shaft on a Pin about z driven at a constant rate (Motion::Steady,
// i.e. prescribed u, q = rate t), two arms pinned to the shaft top about y, the slider on a
// Slider along the shaft; each spring-damper is a TwoPointLinearSpring plus a
// TwoPointLinearDamper between the rod midpoint and the slider centre. Measured: the slider.
Model build_flyball(SimbodyMatterSubsystem& matter, GeneralForceSubsystem& forces) {
    using namespace flyball;
    Force::UniformGravity(forces, matter, Vec3(0, 0, -g));
    Model m;
    const Vec3 shaft_c(0, 0, shaft_com_z);
    Body::Rigid shaft_body(MassProperties(shaft_mass, Vec3(0), Inertia(shaft_inertia[0], shaft_inertia[1], shaft_inertia[2])));
    MobilizedBody::Pin shaft(matter.Ground(), Transform(), shaft_body, Transform(-shaft_c));
    Motion::Steady(shaft, spin_rate);
    m.rate(shaft, spin_rate);
    const Vec3 pivot(0, 0, pivot_z);
    const Rotation about_y = axis_frame(Vec3(0, 1, 0), ZAxis);
    const Vec3 slider_c(0, 0, slider_z);
    Body::Rigid slider_body(MassProperties(slider_mass, Vec3(0), Inertia(slider_inertia)));
    const Rotation along_z = axis_frame(Vec3(0, 0, 1), XAxis);
    MobilizedBody::Slider slider(shaft, Transform(along_z, slider_c - shaft_c), slider_body, Transform(along_z));
    for (double side : {1.0, -1.0}) {  // left arm (x > 0), right arm (mirror image)
        const Vec3 c(side * arm_com[0], arm_com[1], arm_com[2]);
        const Inertia I(arm_inertia[0], arm_inertia[1], arm_inertia[2], arm_inertia[3], side * arm_inertia[4],
                        arm_inertia[5]);
        Body::Rigid arm_body(MassProperties(arm_mass, Vec3(0), I));
        MobilizedBody::Pin arm(shaft, Transform(about_y, pivot - shaft_c), arm_body, Transform(about_y, pivot - c));
        const Vec3 mid(side * arm_spring_point[0], arm_spring_point[1], arm_spring_point[2]);
        Force::TwoPointLinearSpring(forces, arm, mid, slider, Vec3(0), stiffness, rest_length);
        Force::TwoPointLinearDamper(forces, arm, mid, slider, Vec3(0), damping);
    }
    m.measured.push_back({slider, Vec3(0)});
    return m;
}

// The car-axis bump angle phi(t) as a prescribed position-level Motion of the bump's Pin.
class BumpMotion : public Motion::Custom::Implementation {
public:
    Motion::Level getLevel(const State&) const override { return Motion::Position; }
    void calcPrescribedPosition(const State& s, int, Real* q) const override {
        q[0] = car_axis_bump_angle(s.getTime()).phi;
    }
    void calcPrescribedPositionDot(const State& s, int, Real* qd) const override {
        qd[0] = car_axis_bump_angle(s.getTime()).phid;
    }
    void calcPrescribedPositionDotDot(const State& s, int, Real* qdd) const override {
        qdd[0] = car_axis_bump_angle(s.getTime()).phidd;
    }
};

// Test Set car axis as a tree: the bump body turns about the origin at the prescribed angle
// phi(t) (its point (1, 0) is b(t)); the left wheel slides along the bump's y axis (the scene's
// prismatic joint = the constraint x_b x_l + y_b y_l = 0); the right wheel hangs from the left one
// on a massless rod of length L = 1 (the scene's distance joint). The wheels are point masses:
// in the scene their tiny inertia (1e-9) rides on the prescribed bump rotation (left) or on a
// free rotation no force acts on (right), so it does not enter the translational dynamics.
// Springs (k = 1, rest 0.5): origin-left and b(t)-right; g = 1 along -y.
Model build_car_axis(SimbodyMatterSubsystem& matter, GeneralForceSubsystem& forces) {
    Force::UniformGravity(forces, matter, Vec3(0, -1.0, 0));
    Model m;
    const double wheel_mass = 0.0005;
    Body::Rigid bump_body(MassProperties(1.0, Vec3(0), Inertia(1.0)));
    MobilizedBody::Pin bump(matter.Ground(), Transform(), bump_body, Transform());
    Motion::Custom(bump, new BumpMotion);
    const Rotation along_y = axis_frame(Vec3(0, 1, 0), XAxis);
    Body::Rigid wheel(MassProperties(wheel_mass, Vec3(0), Inertia(0)));
    MobilizedBody::Slider left(bump, Transform(along_y), wheel, Transform(along_y));
    MobilizedBody::Pin right(left, Transform(), wheel, Transform(Vec3(-1, 0, 0)));
    m.set_q.push_back([left](State& s) { left.setOneQ(s, 0, 0.5); });
    m.rate(left, 0.0);
    m.rate(right, -car_axis_bump_angle(0).phid);  // rod at rest in the world, the left frame turns
    Force::TwoPointLinearSpring(forces, matter.Ground(), Vec3(0), left, Vec3(0), 1.0, 0.5);
    Force::TwoPointLinearSpring(forces, bump, Vec3(1, 0, 0), right, Vec3(0), 1.0, 0.5);
    m.measured.push_back({left, Vec3(0)});
    m.measured.push_back({right, Vec3(0)});
    return m;
}

// Integrate and print the protocol's output; returns the process status.
int run(MultibodySystem& system, const Model& model, const PeerArgs& a) {
    system.realizeTopology();
    State state = system.getDefaultState();
    for (const auto& f : model.set_q) f(state);
    system.realize(state, Stage::Position);
    for (const auto& f : model.set_u) f(state);
    system.realize(state, Stage::Position);
    system.projectU(state, 1e-12);

    std::unique_ptr<Integrator> integ;
    if (a.integrator == "rk3") integ = std::make_unique<RungeKutta3Integrator>(system);
    else if (a.integrator == "cpodes") integ = std::make_unique<CPodesIntegrator>(system);
    else integ = std::make_unique<RungeKuttaMersonIntegrator>(system);
    integ->setAccuracy(a.value);
    integ->setConstraintTolerance(model.constraint_tolerance > 0 ? model.constraint_tolerance * a.value
                                                                 : std::min(1e-3, a.value));
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
        for (auto& [mb, p] : model.measured) {
            const Vec3 r = mb.findStationLocationInGround(s, p);
            row.insert(row.end(), {r[0], r[1], r[2]});
        }
        rows.push_back(row);
    }
    const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    print_peer_result(cpu, integ->getNumStepsTaken(), rows);
    return 0;
}

}  // namespace

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
        Model model;
        if (a.model == "pendulum_a01") model = build_pendulum(matter, forces);
        else if (const int n = four_bar_loops(a.model)) model = build_four_bar(matter, forces, n);
        else if (const int n = chain_links(a.model)) model = build_chain(matter, forces, n);
        else if (a.model == "gyroscope") model = build_gyroscope(matter, forces);
        else if (a.model == "bricard") model = build_bricard(matter, forces);
        else if (a.model == "flyball") model = build_flyball(matter, forces);
        else if (a.model == "car_axis") model = build_car_axis(matter, forces);
        else {
            std::fprintf(stderr, "simbody peer: unknown model '%s'\n", a.model.c_str());
            return 2;
        }
        return run(system, model, a);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "simbody peer: %s\n", e.what());
        return 1;
    }
}
