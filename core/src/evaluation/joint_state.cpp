// A joint's coordinate and rate, read and written (joint_state.hpp).
#include "evaluation/joint_state.hpp"

#include <mbd/body_poses.hpp>
#include <mbd/sdk/rotation.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <cmath>

namespace mbd {

namespace {

int coordinate_joint(const ModelSystem& system, const std::string& joint) {
    std::string names;
    for (int j = 0; j < system.joint_count(); ++j) {
        const JointInfo& info = system.joint(j);
        if (info.name == joint) {
            if (!info.joint->has_coordinate())
                throw InputError("joint '" + joint + "'", "a " + info.type +
                                                              " joint has no single coordinate to read or write; "
                                                              "set its bodies' states instead (set_body_state)");
            return j;
        }
        names += (names.empty() ? "" : ", ") + info.name;
    }
    throw InputError("joint '" + joint + "'",
                     "the scene has no joint of this name; its joints are: " + (names.empty() ? "none" : names));
}

// s(q) and its row J_s over all nv velocities.
double coordinate_row(const ModelSystem& system, const State& state, int j, Eigen::RowVectorXd& row, bool& periodic) {
    const Model& model = system.model();
    const JointInfo& info = system.joint(j);
    const int per_body = velocities_per_body(model.dimension);
    BodyPoses poses(model);
    poses.update(state);
    CoordinateEval ce;
    ce.J.setZero(per_body * static_cast<int>(info.bodies.size()));
    info.joint->coordinate(poses.view(info.bodies, state.t), ce);
    row.setZero(system.nv());
    for (size_t k = 0; k < info.bodies.size(); ++k)
        if (info.bodies[k] != kGround)
            row.segment(per_body * info.bodies[k], per_body) += ce.J.segment(per_body * static_cast<int>(k), per_body);
    periodic = ce.periodic;
    return ce.value;
}

}  // namespace

JointCoordinate joint_coordinate(ModelSystem& system, const State& state, const std::string& joint) {
    Eigen::RowVectorXd row;
    bool periodic = false;
    const double value = coordinate_row(system, state, coordinate_joint(system, joint), row, periodic);
    return {value, row.dot(state.v)};
}

void set_joint_coordinate(ModelSystem& system, State& state, const std::string& joint, double value, double rate) {
    const int j = coordinate_joint(system, joint);
    const int nv = system.nv();
    ConstraintValues cv;
    Eigen::RowVectorXd row;
    bool periodic = false;
    auto stacked = [&](Eigen::MatrixXd& A) {
        system.constraints(state, cv, true);
        const double s = coordinate_row(system, state, j, row, periodic);
        A.resize(cv.J.rows() + 1, nv);
        A.topRows(cv.J.rows()) = Eigen::MatrixXd(cv.J);
        A.bottomRows(1) = row;
        return periodic ? wrap_angle(s - value) : s - value;
    };
    Eigen::MatrixXd A;
    for (int iteration = 0;; ++iteration) {
        const double ds = stacked(A);
        Eigen::VectorXd r(A.rows());
        r << cv.C, ds;
        if (r.lpNorm<Eigen::Infinity>() <= 1e-12) break;
        if (iteration == 50 || !r.allFinite())
            throw KinematicsError("joint '" + joint + "': the mechanism could not be brought to the coordinate " +
                                  std::to_string(value) + " (residual " + std::to_string(r.lpNorm<Eigen::Infinity>()) +
                                  " after 50 Newton iterations): a position it cannot reach?");
        const Eigen::VectorXd dq = -A.completeOrthogonalDecomposition().solve(r);
        system.advance_positions(state.q, dq);
    }
    stacked(A);
    Eigen::VectorXd b(A.rows());
    b << -cv.C_t, rate;
    state.v += A.completeOrthogonalDecomposition().solve(b - A * state.v);
}

}  // namespace mbd
