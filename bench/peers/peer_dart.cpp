// DART peer of the work-precision benchmark (bench/peers/peer_common.hpp): a URDF model file read
// by DART's own URDF reader (dart::utils::DartLoader, Debian libdart-utils-urdf-dev) and either
// stepped by its World (`euler`), whose only integrator is semi-implicit Euler (first order:
// velocities, then positions with the new velocities), or (`rk4`) DART's forward dynamics
// (Skeleton::computeForwardDynamics, its articulated-body algorithm, with the joints' springs and
// dampers) integrated by classical RK4 in the joint positions and velocities, as
// tests/test_dart_agreement.cpp does; either at the given step, shortened so that the output step
// is a whole number of steps. Gravity is DART's default, 9.81 along -z, the URDF convention. The
// reader gets the file without its <visual> and <collision> elements: the dynamics uses the
// explicit <inertial> only, and DART refuses a model whose meshes it cannot resolve (package://
// paths of robots shipped without their meshes). No collision detection runs (no shapes). Where
// DART's reader departs from URDF's meaning (a link without <inertial>, a root link without
// a parent joint), the peer gives it URDF's (read_urdf).
// The benchmark's named models are not URDF files: the peer exits with status 2 for them.
#include "peer_common.hpp"

#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>
#include <dart/utils/urdf/DartLoader.hpp>

#include <ctime>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

namespace {

dart::dynamics::SkeletonPtr read_urdf(const std::string& file) {
    std::ifstream in(file);
    if (!in) {
        std::fprintf(stderr, "dart peer: cannot read %s\n", file.c_str());
        return nullptr;
    }
    std::stringstream text;
    text << in.rdbuf();
    static const std::regex geometry("<visual[\\s>][\\s\\S]*?</visual>|<collision[\\s>][\\s\\S]*?</collision>");
    // DART's reader warns on std::cerr (e.g. of the massless links welded to the world); held
    // back so that the first line `mbd bench` reads is the peer's "cpu_s steps", shown on failure
    std::ostringstream warnings;
    std::streambuf* const cerr = std::cerr.rdbuf(warnings.rdbuf());
    // URDF's meaning where DART's reader has its own defaults: a link without <inertial> is
    // massless (DART: 1 kg), a root link without a parent joint is fixed (DART: floating), as
    // MuJoCo and mbd read the file
    using Loader = dart::utils::DartLoader;
    Loader loader(Loader::Options(nullptr, Loader::RootJointType::FIXED,
                                  dart::dynamics::Inertia(0.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero())));
    auto robot = loader.parseSkeletonString(std::regex_replace(text.str(), geometry, ""),
                                            dart::common::Uri::createFromPath(file));
    std::cerr.rdbuf(cerr);
    if (!robot) std::fprintf(stderr, "dart peer: DART's URDF reader refused %s: %s\n", file.c_str(), warnings.str().c_str());
    return robot;
}

// The initial joint velocities by joint name; false (with a message) for an unknown joint or a
// count of numbers other than the joint's degrees of freedom.
bool set_velocities(const PeerArgs& a, dart::dynamics::Skeleton& robot) {
    for (const auto& [name, v] : a.velocities) {
        dart::dynamics::Joint* joint = robot.getJoint(name);
        if (!joint || joint->getNumDofs() != v.size() || v.size() != 1) {
            std::fprintf(stderr, "dart peer: no one-degree-of-freedom joint '%s' for its initial velocity\n", name.c_str());
            return false;
        }
        joint->setVelocity(0, v[0]);
    }
    return true;
}

// One classical RK4 step of DART's forward dynamics in y = (q, v).
void rk4_step(dart::dynamics::Skeleton& robot, double h, Eigen::VectorXd& y) {
    const Eigen::Index n = static_cast<Eigen::Index>(robot.getNumDofs());
    auto rate = [&](const Eigen::VectorXd& x) {
        robot.setPositions(x.head(n));
        robot.setVelocities(x.tail(n));
        robot.computeForwardDynamics();
        Eigen::VectorXd xdot(2 * n);
        xdot << x.tail(n), robot.getAccelerations();
        return xdot;
    };
    const Eigen::VectorXd k1 = rate(y), k2 = rate(y + 0.5 * h * k1), k3 = rate(y + 0.5 * h * k2), k4 = rate(y + h * k3);
    y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    robot.setPositions(y.head(n));  // the state reached, for the bodies' mass centres
    robot.setVelocities(y.tail(n));
}

}  // namespace

int main(int argc, char** argv) {
    const PeerArgs a = parse_peer_args(argc, argv);
    if (!is_model_file(a.model) || a.model.size() < 5 || a.model.substr(a.model.size() - 5) != ".urdf") {
        std::fprintf(stderr, "dart peer: reads URDF model files only, not '%s'\n", a.model.c_str());
        return 2;
    }
    const bool rk4 = a.integrator == "rk4";
    if (a.tolerance || (!a.integrator.empty() && !rk4 && a.integrator != "euler" && a.integrator != "default")) {
        std::fprintf(stderr, "dart peer: fixed steps only, of DART's semi-implicit Euler (euler) or of RK4 over DART's "
                             "forward dynamics (rk4), step VALUE\n");
        return 2;
    }
    const dart::dynamics::SkeletonPtr robot = read_urdf(a.model);
    if (!robot || !set_velocities(a, *robot)) return 2;
    std::vector<dart::dynamics::BodyNode*> bodies;
    for (const std::string& name : a.bodies) {
        bodies.push_back(robot->getBodyNode(name));
        if (!bodies.back()) {
            std::fprintf(stderr, "dart peer: no link '%s' in %s\n", name.c_str(), a.model.c_str());
            return 2;
        }
    }
    const long per_output = std::max(1L, static_cast<long>(std::ceil(a.output_step / a.value - 1e-9)));
    const double h = a.output_step / per_output;
    auto world = dart::simulation::World::create();
    world->setGravity(Eigen::Vector3d(0, 0, -9.81));
    world->setTimeStep(h);
    world->addSkeleton(robot);
    robot->setGravity(Eigen::Vector3d(0, 0, -9.81));  // the World gives it its own; the rk4 path does not step the World
    Eigen::VectorXd y(2 * robot->getNumDofs());
    y << robot->getPositions(), robot->getVelocities();
    const std::vector<double> times = peer_output_times(a);
    std::vector<std::vector<double>> rows;
    long steps = 0;
    const std::clock_t start = std::clock();
    for (double t : times) {
        for (const long target = std::lround(t / h); steps < target; ++steps) rk4 ? rk4_step(*robot, h, y) : world->step();
        std::vector<double> row{t};
        for (dart::dynamics::BodyNode* b : bodies) {
            const Eigen::Vector3d c = b->getCOM();
            row.insert(row.end(), {c.x(), c.y(), c.z()});
        }
        rows.push_back(row);
    }
    const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    print_peer_result(cpu, steps, rows);
    return 0;
}
