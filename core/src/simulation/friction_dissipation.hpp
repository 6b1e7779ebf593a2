// The energy dissipated by dry friction, integrated with the motion: the run's ODE gets one
// more state, E_f with E_f' = -sum_f Q_f^T v over the friction elements (Force::is_friction;
// System::friction_power, at the loads the formulation solved in the same evaluation), so
// E_f is integrated by the run's integrator to its tolerance, like the motion, and for a
// scene whose other forces are conservative  E(0) - E(t) = E_f(t)  holds to that tolerance
// (the diagnostics column friction_dissipated, docs/formulations.md "Diagnostics").
// It is added only with --diagnostics: the extra state takes part in the error control of the
// explicit integrators, so a run without the column keeps the steps it had (docs/formulations.md).
// cvode leaves it out (quadrature_count): in the stiff creep of a stuck pin its rate, the
// friction power, follows the fast relaxation of the slip rate, and its error test failed
// where the motion's passes (scenes/extreme/pin-friction-holds.yaml at 1e-10).
#pragma once

#include <mbd/integrator.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mbd {

class FrictionDissipationProblem final : public OdeProblem {
public:
    FrictionDissipationProblem(OdeProblem& motion, Formulation& formulation, System& system)
        : motion_(motion), formulation_(formulation), system_(system), n_(motion.size()) {
        head_.setZero(n_);
        head_dot_.setZero(n_);
    }
    // y = [y_motion; E_f]
    int size() const override { return n_ + 1; }
    int quadrature_count() const override { return 1; }
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override {
        head_ = y.head(n_);
        motion_.rhs(t, head_, head_dot_);  // also sets the reaction loads of this evaluation
        ydot.resize(n_ + 1);
        ydot.head(n_) = head_dot_;
        formulation_.from_ode(t, head_, state_);
        ydot[n_] = -system_.friction_power(state_);
    }
    bool project(double t, Eigen::VectorXd& y) override { return on_head(y, [&] { return motion_.project(t, head_); }); }
    bool state_redefined() override { return motion_.state_redefined(); }
    bool may_redefine_state() const override { return motion_.may_redefine_state(); }
    int event_count() const override { return motion_.event_count(); }
    double next_breakpoint(double t) const override { return motion_.next_breakpoint(t); }
    void set_step_end(double t) override { motion_.set_step_end(t); }
    void event_values(double t, const Eigen::VectorXd& y, Eigen::VectorXd& g) override {
        head_ = y.head(n_);
        motion_.event_values(t, head_, g);
    }
    bool handle_events(double t, Eigen::VectorXd& y, const std::vector<int>& crossed, std::vector<int>& side) override {
        return on_head(y, [&] { return motion_.handle_events(t, head_, crossed, side); });
    }
    std::string describe_event(int event) const override { return motion_.describe_event(event); }

private:
    // run `act` on the motion's part of y (in head_) and write it back
    template <class Act>
    bool on_head(Eigen::VectorXd& y, const Act& act) {
        head_ = y.head(n_);
        const bool result = act();
        y.head(n_) = head_;
        return result;
    }
    OdeProblem& motion_;
    Formulation& formulation_;
    System& system_;
    int n_;
    Eigen::VectorXd head_, head_dot_;
    State state_;
};

}  // namespace mbd
