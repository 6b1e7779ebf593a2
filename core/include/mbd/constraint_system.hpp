// The assembler of constraint equations: stacks the rows of every joint and
// driver into C(q, t), the sparse Jacobian C_q (with respect to v), C_t and
// gamma (book Eqs. 3.108-3.124), and remembers which element owns each row.
#pragma once

#include <mbd/body_poses.hpp>
#include <mbd/model.hpp>

#include <Eigen/Sparse>

#include <string>
#include <vector>

namespace mbd {

struct RowOwner {
    enum class Kind { Joint, Driver };
    Kind kind = Kind::Joint;
    int element = -1;        // index into Model::joints or Model::drivers
    int local_row = 0;
    std::string element_name;
    std::string row_name;    // the joint's own row name, or "coordinate" for drivers

    std::string describe() const;  // e.g. "joint 'O' (row x)" or "driver 'motor'"
};

class ConstraintSystem {
public:
    // include_drivers = false gives the joints only (dynamically driven model).
    explicit ConstraintSystem(const Model& model, bool include_drivers = true);

    const Model& model() const { return *model_; }
    int rows() const { return rows_; }
    int joint_rows() const { return joint_rows_; }
    int cols() const { return model_->nv(); }
    const RowOwner& owner(int row) const { return owners_[row]; }

    // Evaluate every row at the given state.
    void evaluate(const State& state, ConstraintValues& out) const;

private:
    const Model* model_;
    bool include_drivers_;
    int rows_ = 0;
    int joint_rows_ = 0;
    std::vector<int> joint_offset_;
    std::vector<RowOwner> owners_;
    // scratch, allocated once
    mutable BodyPoses poses_;
    mutable std::vector<ConstraintEval> joint_eval_;
    mutable std::vector<CoordinateEval> driver_eval_;
    mutable std::vector<Eigen::Triplet<double>> triplets_;
    mutable BodyStates view_;
};

}  // namespace mbd
