// Trust-region continuation of the statics solve (see branch_check.hpp): solve in
// the box around the centre; verify that the step stays on the start's assembly
// branch (else shrink the box and solve again from the same centre); re-centre on
// the solution while it lies on the box. Debugging aid (tests):
// MBD_STATICS_TRUST_REGION=off: no box; =F (a number > 0): the box starts F times its size.
#pragma once

#include "branch_check.hpp"
#include "evaluator.hpp"
#include "statics_nlp.hpp"

#include <IpIpoptApplication.hpp>

#include <string>

namespace mbd::ipopt_plugin {

struct ContinuationResult {
    Ipopt::ApplicationReturnStatus status = Ipopt::Internal_Error;  // of the last solve
    Ipopt::SmartPtr<StaticsNLP> nlp;                                // the last solve
    Eigen::VectorXd centre;  // the last configuration reached on the start's branch
    int segments = 0, rejected = 0, iterations = 0;
    double factor = 1.0;    // the final box size, in units of the initial box
    std::string failure;    // why the continuation stopped short of a solution (empty: it did not)
    double ctol = 0.0;      // the assembly tolerance on |C|
};

class Continuation {
public:
    // q0: the start; lambda0: starting multipliers (virtual work).
    Continuation(System& sys, Evaluator& ev, const StaticsOptions& opt, bool potential, const Eigen::VectorXd& q0,
                 const Eigen::VectorXd& lambda0);
    ContinuationResult run(Ipopt::IpoptApplication& app);

private:
    enum class Verdict { Accept, Shrink, Stop };
    // The box |x_i| <= bound[i] of the current factor (empty without a trust region).
    Eigen::VectorXd box() const;
    // Whether the solve's step x may be taken (q_end_: its projection onto C = 0).
    Verdict judge(const Eigen::VectorXd& x, bool at_bound, ContinuationResult& out);
    // Moves the centre and the starting multipliers to the accepted step.
    void accept(const Eigen::VectorXd& x, ContinuationResult& out);

    System& sys_;
    Evaluator& ev_;
    const StaticsOptions& opt_;
    bool potential_;
    Eigen::VectorXd q0_;
    bool trust_ = true;
    double factor_max_ = 1.0, factor_ = 1.0;
    IncrementGeometry geo_;
    Projector projector_;
    Eigen::VectorXd tail_, q_end_;
};

}  // namespace mbd::ipopt_plugin
