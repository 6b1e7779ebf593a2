// The assembler of constraint equations: stacks the rows of every joint and
// driver into C(q, t), the sparse Jacobian C_q (with respect to v), C_t and
// gamma (book Eqs. 3.108-3.124), and remembers which element owns each row.
// Optionally the joints' velocity-level (nonholonomic) rows A v = b follow the drivers,
// written as rows with no position residual (C = 0, J = A, C_t = -b: kit system.hpp).
// It is immutable: the Jacobian's sparsity pattern (every body block of every row,
// zeros included) is fixed when it is built, and each evaluation writes the values
// in place, into the caller's Data and ConstraintValues.
#pragma once

#include <mbd/data.hpp>
#include <mbd/element_bodies.hpp>
#include <mbd/model.hpp>

#include <Eigen/Sparse>

#include <string>
#include <vector>

namespace mbd {

struct RowOwner {
    enum class Kind { Joint, Driver, JointVelocity };  // JointVelocity: a velocity-level row
    Kind kind = Kind::Joint;
    int element = -1;        // index into Model::joints or Model::drivers
    int local_row = 0;
    std::string element_name;
    std::string row_name;    // the joint's own row name, or "coordinate" for drivers

    std::string describe() const;  // e.g. "joint 'O' (row x)" or "driver 'motor'"
};

class ConstraintSystem {
public:
    // include_drivers = false gives the joints only (dynamically driven model);
    // include_velocity_rows adds the joints' velocity-level rows after the drivers.
    explicit ConstraintSystem(const Model& model, bool include_drivers = true, bool include_velocity_rows = false);

    const Model& model() const { return *model_; }
    int rows() const { return rows_; }
    int joint_rows() const { return joint_rows_; }
    int cols() const { return model_->nv(); }
    const RowOwner& owner(int row) const { return owners_[row]; }

    // Evaluate every row at the given state, writing the rows into `data` and `out`.
    void evaluate(const State& state, Data& data, ConstraintValues& out) const;
    // gamma alone (the joints' and drivers' rows; not the velocity-level rows): the joints are
    // evaluated as by evaluate(), but nothing else is copied or scattered
    void evaluate_gamma(const State& state, Data& data, Eigen::VectorXd& gamma) const;
    // out += (d gamma / d v)^T mu over the rows of the joints that provide it
    // (Joint::has_gamma_velocity_transpose); other rows add nothing
    void gamma_velocity_transpose(const State& state, Data& data, const Eigen::VectorXd& mu, Eigen::VectorXd& out) const;

    // Joint j's slot `slot` on a flexible body (System::joint_material_frame): the material frame's
    // pose and the joint's Jacobian over its velocities at `state`; false for a rigid slot.
    bool material_frame(size_t j, int slot, const State& state, Data& data, Mat3& A, Vec3& R,
                        Eigen::MatrixXd& J_frame) const;
    // The same for driver d's row (System::driver_material_frame; J_frame 1 x velocities_per_body).
    bool driver_material_frame(size_t d, int slot, const State& state, Data& data, Mat3& A, Vec3& R,
                               Eigen::MatrixXd& J_frame) const;

private:
    // joint j evaluated at the posed state into data.joint_rows[j]
    const ConstraintEval& evaluate_joint(size_t j, const State& state, Data& data) const;
    // the named error of joint j's non-finite output, unless the state itself is not finite
    void throw_if_state_finite(size_t j, const ConstraintEval& e, const State& state) const;
    // a material frame's pose as a body's (planar: embedded in 3D)
    void frame_pose(const MaterialFrame& frame, Mat3& A, Vec3& R) const;
    // data.view for an element of the joint's bodies; its flexible slots' material frames (if any)
    // computed into `slots` and put in place of the ground the slots hold
    static void fill_joint_view(BodyList bodies, const std::vector<FlexibleAttachment>& flexible,
                                std::vector<Data::FlexibleSlot>& slots, double t, Data& data);
    // the chain rule onto each flexible slot of rows J over the joint's bodies (the joint's or its
    // driver's rows): slots[a].J = J_f G and gamma -= J_f a (sdk body.hpp)
    void map_flexible_slots(const std::vector<FlexibleAttachment>& flexible, std::vector<Data::FlexibleSlot>& slots,
                            const Eigen::Ref<const Eigen::MatrixXd>& J, Eigen::Ref<Eigen::VectorXd> gamma) const;
    // driver d's coordinate into data.driver_rows[d], and its motion f(t) (finite, or a named error)
    const CoordinateEval& evaluate_driver(size_t d, const State& state, Data& data, TimeValue& f) const;
    // evaluate()'s writer of the Jacobian's values, one slot_ entry after another
    struct JacobianScatter;
    // evaluate()'s sections after the joints' rows: the drivers', then the velocity-level rows
    void evaluate_drivers(const State& state, Data& data, ConstraintValues& out, JacobianScatter& J) const;
    void evaluate_velocity_rows(const State& state, Data& data, ConstraintValues& out, JacobianScatter& J) const;

    const Model* model_;
    bool include_drivers_;
    bool include_velocity_rows_;
    int rows_ = 0;
    int joint_rows_ = 0;
    std::vector<int> joint_offset_;
    // each joint's bodies and its Joint, read in order by the evaluation loops (element_bodies.hpp)
    ElementBodies joint_bodies_;
    std::vector<const Joint*> joint_;
    std::vector<const std::vector<FlexibleAttachment>*> flexible_;  // each joint's slots on flexible bodies
    std::vector<int> velocity_offset_;  // each joint's first velocity-level row
    std::vector<RowOwner> owners_;
    // The Jacobian's fixed pattern, and for each element row and each of its body
    // columns (in the order evaluate() visits them, ground bodies skipped) the index
    // of that entry in the pattern's value array.
    Eigen::SparseMatrix<double> pattern_;
    std::vector<int> slot_;
};

}  // namespace mbd
