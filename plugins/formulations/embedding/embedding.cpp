// The embedding formulation of the equations of motion (Shabana, Computational Dynamics,
// Sec. 4.5 and Sec. 6.5, Eqs. 6.79-6.99; coordinate partitioning Sec. 6.12):
//     qdot = B qdot_i,   B^T M B qddot_i = B^T (Q - M gamma')        (book Eq. 6.95)
// in the minimum number of equations (the degrees of freedom), with the constraint
// rows (the System's joints and drivers) eliminated.
//
// Three paths, chosen from the scene (path: auto) or forced (path: dense | recursive | closure):
//   recursive  (plugins/formulations/articulated_body/) the joints form a tree, every joint describes its relative
//              motion and every driver drives a joint of one freedom: joint coordinates, a driven
//              joint's motion prescribed (it leaves the ODE), O(n) articulated-body algorithm; no
//              constraint drift by construction.
//   closure    (articulated_body/loop_closure.hpp) closed loops: a spanning tree of the
//              joints with a supported relative motion in joint coordinates, the other joints'
//              and the drivers' rows as loop-closure rows, solved by the augmented method in
//              joint space (Eq. 6.141 with M_u = H^T M H, Phi_u = J_c H); auto takes it unless
//              a joint has velocity-level rows, no joint can be a tree edge, or `independent:`
//              names coordinates for the dense path.
//   dense      (partitioned.hpp) anything else (velocity-level (nonholonomic) rows, or forced):
//              absolute coordinates, independent velocity components chosen by
//              rank-revealing LU of J (partition.hpp), dependent positions by Newton-Raphson
//              after each step, re-selection near singular configurations.
// The choice is logged (FormulationOptions::log) ("embedding: recursive path (...)") and printed by
// `mbd check` (topology.hpp: recursive_embedding_possible).
#include "partitioned.hpp"
#include "planar_articulated_body.hpp"
#include "loop_closure.hpp"
#include <mbd/kit/rank_certificate.hpp>

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/singularity.hpp>
#include <mbd/kit/topology.hpp>

#include <iostream>
#include <memory>

namespace mbd {
namespace {

class Embedding final : public Formulation {
public:
    explicit Embedding(const FormulationSpec& spec);
    OptionGroups options_used() const override { return kPartitionOptions | kNewtonOptions | kSingularityOptions; }
    // the dense path partitions the velocity-level rows with the others (partitioned.hpp);
    // a scene with them is no tree of relative joint motions, so auto never takes the recursive one
    bool supports_velocity_constraints() const override { return true; }

    void bind(System& system, const FormulationOptions& options) override {
        std::string reason;
        const bool tree = recursive_embedding_possible(system, &reason);
        std::string closure_reason;
        const bool closure_possible = !tree && closure_embedding_possible(system, &closure_reason);
        path_taken_ = path_ != "auto"                       ? path_
                      : tree                                ? "recursive"
                      : closure_possible && independent_.empty() ? "closure"
                                                            : "dense";
        if (path_taken_ == "closure" && !tree) reason = closure_reason;
        const int nonholonomic = system.first_nonholonomic_joint();
        if (path_taken_ != "dense" && nonholonomic >= 0)
            throw InputError("", "embedding formulation, path: " + path_taken_ + ": joint '" + system.joint(nonholonomic).name +
                                     "' (" + system.joint(nonholonomic).type +
                                     ") has velocity-level (nonholonomic) rows, which the recursive path (joint "
                                     "coordinates of a tree) cannot hold; use path: dense (or auto)");
        if (path_taken_ == "recursive")
            impl_ = std::make_unique<articulated::PlanarArticulatedBody>();  // spatial algebra unless planar
        else if (path_taken_ == "closure")
            impl_ = std::make_unique<articulated::LoopClosure>();
        else
            impl_ = std::make_unique<embedding::Partitioned>(independent_);
        // the recursive path says whether it runs in planar algebra, known once bound; the others
        // log before binding, which may name redundant rows
        const auto* recursive = dynamic_cast<const articulated::PlanarArticulatedBody*>(impl_.get());
        if (!recursive) log_path(options, reason);
        impl_->bind(system, options);
        if (recursive) log_path(options, reason + (recursive->planar_algebra() ? ", planar algebra" : ""));
        system_ = &system;
        singularity_.tolerance = options.singularity_tolerance;
        singularity_.reset();
        if (path_taken_ != "recursive") rank_certificate_.bind(system, singularity_);
    }
    void log_path(const FormulationOptions& options, const std::string& reason) const {
        if (options.log_choices.value_or(true))
            options.log("embedding: " + path_taken_ + " path (" + reason +
                        (path_ != "auto" ? "; forced by path: " + path_ : std::string()) + ")");
    }
    int ode_size() const override { return impl_->ode_size(); }
    void to_ode(const State& state, Eigen::VectorXd& y) override { impl_->to_ode(state, y); }
    void from_ode(double t, const Eigen::VectorXd& y, State& state) override { impl_->from_ode(t, y, state); }
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override { impl_->rhs(t, y, ydot); }
    bool project(double t, Eigen::VectorXd& y) override {
        // a rank drop of J (joints + drivers) at the accepted state is a singular configuration
        // (singularity.hpp), checked once per accepted step; not on the recursive path, where
        // the rows of a tree are independent by construction. The closure path checks all the
        // System's rows (a loop that locks drops the rank of the whole J) with the J its
        // projection evaluated at the projected positions; when the projection fails or stops
        // (across a singular position), the check runs first at the unprojected state, so that
        // the rank drop is named rather than the projection's own, less specific error.
        if (path_taken_ == "closure") return project_closure(t, y);
        if (!impl_->project(t, y)) return false;
        if (path_taken_ == "dense") check_singularity(t, y);
        return true;
    }
    bool state_redefined() override { return impl_->state_redefined(); }
    bool may_redefine_state() const override { return !impl_ || impl_->may_redefine_state(); }
    void multipliers(const State& state, Eigen::VectorXd& lambda) override { impl_->multipliers(state, lambda); }
    void accelerations(const State& state, Eigen::VectorXd& vdot) override { impl_->accelerations(state, vdot); }

private:
    bool project_closure(double t, Eigen::VectorXd& y) {
        bool projected = false;
        try {
            projected = impl_->project(t, y);  // y is left as it was unless it succeeds
        } catch (const DynamicsError&) {
            check_singularity(t, y);
            throw;
        }
        if (!projected) {
            check_singularity(t, y);
            return false;
        }
        if (singularity_.active(*system_))
            singularity_.check(*system_, t, static_cast<const articulated::LoopClosure&>(*impl_).projected_jacobian());
        return true;
    }
    void check_singularity(double t, const Eigen::VectorXd& y) {
        if (!singularity_.active(*system_)) return;
        impl_->from_ode(t, y, check_state_);
        system_->constraints_with_velocity_rows(check_state_, check_cv_, true);
        singularity_.check(*system_, t, check_cv_.J);
    }

    // the embedding's own keys
    std::string path_ = "auto";             // auto | dense | recursive | closure
    std::vector<std::string> independent_;  // velocity components to prefer as independent ("crank.angle")
    std::unique_ptr<Formulation> impl_;
    std::string path_taken_;  // recursive | closure | dense
    System* system_ = nullptr;
    SingularityMonitor singularity_;
    RankCertificate rank_certificate_;  // lent to singularity_ (support/rank_certificate.hpp)
    State check_state_;
    ConstraintValues check_cv_;
};

// Reads the embedding's own keys; the host reads the shared ones and refuses any other.
Embedding::Embedding(const FormulationSpec& spec) {
    const Params& params = spec.params;
    if (params.has("path")) {
        path_ = params.string("path");
        if (path_ != "auto" && path_ != "dense" && path_ != "recursive" && path_ != "closure")
            params.at("path").fail("'path' must be auto, dense, recursive or closure, got '" + path_ + "'");
    }
    if (params.has("independent")) {
        const Param& p = params.at("independent");
        if (p.is_scalar())
            independent_.push_back(p.text);
        else if (p.is_list())
            for (const Param& item : p.items) independent_.push_back(item.text);
        else
            p.fail("'independent' must be a velocity component name or a list of them (e.g. [crank.angle])");
    }
}

}  // namespace

std::unique_ptr<Formulation> make_embedding(const FormulationSpec& spec) { return std::make_unique<Embedding>(spec); }

}  // namespace mbd

MBD_FORMULATION_PLUGIN(embedding, mbd::make_embedding)
