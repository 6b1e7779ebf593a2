// The core's implementation of the SDK's System: one Model (shared, immutable) and
// the Data this System evaluates into (its own). What formulation, statics and
// inverse-dynamics plugins see. One ModelSystem per thread; any number per Model.
#pragma once

#include <mbd/constraint_system.hpp>
#include <mbd/data.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/model.hpp>
#include <mbd/kit/system.hpp>
#include <mbd/kit/varying_mass.hpp>

#include <functional>
#include <memory>
#include <utility>

namespace mbd {

class ModelSystem final : public System, public VaryingMass {
public:
    explicit ModelSystem(const Model& model, KinematicsOptions kinematics = {});
    ModelSystem(Model&&, KinematicsOptions = {}) = delete;  // it keeps a reference: no temporaries

    const Model& model() const { return *model_; }
    Data& data() { return data_; }

    Dimension dimension() const override { return model_->dimension; }
    const std::string& name() const override { return model_->name; }
    int body_count() const override { return model_->body_count(); }
    const BodyInfo& body(int index) const override { return bodies_.at(index); }
    Vec3 gravity() const override { return model_->gravity; }
    int flexible_coordinates() const override { return model_->flexible_coordinates(); }
    bool joint_material_frame(const State& state, int joint, int slot, Mat3& A, Vec3& R,
                              Eigen::MatrixXd& J_frame) override {
        return joints_only_.material_frame(static_cast<size_t>(joint), slot, state, data_, A, R, J_frame);
    }
    bool driver_material_frame(const State& state, int driver, int slot, Mat3& A, Vec3& R,
                               Eigen::MatrixXd& J_frame) override {
        return with_drivers_.driver_material_frame(static_cast<size_t>(driver), slot, state, data_, A, R, J_frame);
    }
    int joint_count() const override { return static_cast<int>(joints_.size()); }
    const JointInfo& joint(int index) const override { return joints_.at(index); }
    int driver_count() const override { return static_cast<int>(drivers_.size()); }
    const DriverInfo& driver(int index) const override { return drivers_.at(index); }
    TimeValue driver_motion(int index, double t) const override { return model_->drivers.at(index).motion->evaluate(t); }
    int force_count() const override { return static_cast<int>(forces_.size()); }
    const ForceInfo& force(int index) const override { return forces_.at(index); }
    std::string describe_row(int row) const override;

    State initial_state() const override { return model_->initial_state(); }
    void advance_positions(Eigen::VectorXd& q, const Eigen::VectorXd& dv) const override;
    Eigen::VectorXd coordinate_rates(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const override;
    void normalize(Eigen::VectorXd& q) const override;

    const Eigen::SparseMatrix<double>& mass_matrix() const override { return mass_; }
    void generalized_forces(const State& state, Eigen::VectorXd& Q) override;
    void force_jacobians(const State& state, Eigen::SparseMatrix<double>& dQ_dq,
                         Eigen::SparseMatrix<double>& dQ_dv) override;
    double kinetic_energy(const State& state) const override;
    // the flexible bodies whose mass matrix varies (kit varying_mass.hpp)
    const std::vector<Block>& varying_mass_blocks() const override { return varying_blocks_; }
    void update_mass_matrix(const Eigen::VectorXd& q) override;
    double potential_energy(const State& state) override;
    bool conservative() const override;

    // A force the program computes (Simulator::set_user_force): called by every
    // generalized_forces after the elements, it adds its generalized forces to Q (size nv).
    // force_jacobians leaves it out (its Jacobians are taken as zero). Empty: none.
    using ExtraForce = std::function<void(const State& state, Eigen::VectorXd& Q)>;
    void set_extra_force(ExtraForce force) { extra_force_ = std::move(force); }

    const std::vector<int>& reaction_loaded_forces() const override { return reaction_loaded_; }
    void set_reaction_loads(const Eigen::VectorXd& loads) override;
    const Eigen::VectorXd& reaction_loads() const override { return loads_; }
    void reaction_load_directions(const State& state, Eigen::MatrixXd& G, std::vector<Vec3>& axes) override;
    bool has_friction() const override { return !friction_.empty(); }
    double friction_power(const State& state) override;

    void constraints(const State& state, ConstraintValues& out, bool include_drivers = true) override;
    void constraint_gamma(const State& state, Eigen::VectorXd& gamma, bool include_drivers = true) override;
    void gamma_velocity_transpose(const State& state, const Eigen::VectorXd& mu, Eigen::VectorXd& out) override;
    void constraints_with_velocity_rows(const State& state, ConstraintValues& out, bool include_drivers = true) override;
    void assemble(State& state, bool include_drivers = true) override;
    void consistent_velocities(State& state, bool include_drivers = true) override;

private:
    // element f's Q into data_.force_Q (its body blocks), at its reaction load if it has one
    Eigen::Ref<Eigen::VectorXd> element_force(int f, double t);
    // d Q_v / dq and d Q_v / dv of a flexible body whose mass varies, by central differences
    void quadratic_velocity_differences(const FlexibleBodyInstance& f, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                        std::vector<Eigen::Triplet<double>>& tq,
                                        std::vector<Eigen::Triplet<double>>& tv) const;
    void force_differences(const ForceInstance& f, const State& state, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                           Eigen::Ref<Eigen::MatrixXd> dQ_dv);

    const Model* model_;
    KinematicsOptions kinematics_;
    std::vector<BodyInfo> bodies_;
    std::vector<JointInfo> joints_;
    std::vector<DriverInfo> drivers_;
    std::vector<ForceInfo> forces_;
    ElementBodies force_bodies_;  // each force's bodies, read in order by generalized_forces (element_bodies.hpp)
    Eigen::SparseMatrix<double> mass_;
    std::vector<Block> varying_blocks_;  // their blocks in mass_ (stored dense, every entry)
    std::vector<int> varying_bodies_;    // their indices in Model::flexible_bodies
    const ConstraintSystem with_drivers_;
    const ConstraintSystem joints_only_;
    const ConstraintSystem with_drivers_and_velocity_rows_;
    const ConstraintSystem joints_and_velocity_rows_;
    Data data_;
    Eigen::VectorXd flexible_Q_;  // one flexible body's force (the widest), workspace
    // the constant-load elements' summed Q (model.hpp ForceInstance::constant_load: the core's
    // gravity, m g at every mass centre, independent of t, q and v), evaluated at the first
    // generalized_forces and added as one vector after it
    std::vector<int> varying_forces_;  // the other elements, in scene order
    Eigen::VectorXd constant_Q_;
    bool constant_Q_ready_ = false;
    std::vector<int> reaction_loaded_;  // force indices with a load_joint, in scene order
    std::vector<int> load_slot_;        // per force: its index in loads_, -1 none
    Eigen::VectorXd loads_;             // their loads N (set_reaction_loads)
    std::vector<int> friction_;         // force indices of the dry-friction elements
    ExtraForce extra_force_;
};

}  // namespace mbd
