// Trust-region continuation of the statics solve (continuation.hpp).
#include "continuation.hpp"

#include "ipopt_common.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace mbd::ipopt_plugin {
namespace {

constexpr int kMaxSegments = 100;
constexpr double kMinFactor = 1.0 / 256;

std::string branch_jump_message(bool trust) {
    std::ostringstream msg;
    msg << "the solver jumped to another assembly branch: the equilibrium it found is not connected to "
           "the assembled start along the constraint manifold C(q) = 0 (marching from the start "
           "to it, the projections onto C = 0 break off"
        << (trust ? ", even with the step box shrunk to 1/256" : ", no step box")
        << "), so the linkage cannot reach it without coming apart; start the scene closer to the "
           "expected equilibrium, on the assembly you mean, or add joint limits";
    return msg.str();
}

}  // namespace

Continuation::Continuation(System& sys, Evaluator& ev, const StaticsOptions& opt, bool potential,
                           const Eigen::VectorXd& q0, const Eigen::VectorXd& lambda0)
    : sys_(sys), ev_(ev), opt_(opt), potential_(potential), q0_(q0), geo_(increment_geometry(sys, q0)),
      projector_(sys), tail_(lambda0) {
    const char* tr_env = std::getenv("MBD_STATICS_TRUST_REGION");
    trust_ = !(tr_env && std::string(tr_env) == "off");
    if (trust_ && tr_env && std::atof(tr_env) > 0) factor_max_ = std::atof(tr_env);
    factor_ = factor_max_;
    if (!potential_) {
        const int mc = sys.constraint_rows(true), nl = static_cast<int>(opt.limits.size());
        tail_ = Eigen::VectorXd::Zero(mc + 2 * nl);
        tail_.head(lambda0.size()) = lambda0;
    }
}

ContinuationResult Continuation::run(Ipopt::IpoptApplication& app) {
    ContinuationResult out;
    out.ctol = std::max(1e-9, 10.0 * opt_.tolerance) * std::max(1.0, geo_.length);
    out.centre = q0_;
    for (;;) {
        const Eigen::VectorXd bound = box();
        out.nlp = new StaticsNLP(ev_, out.centre, opt_.limits, potential_, opt_.hessian != "limited-memory", tail_,
                                 bound);
        out.status = app.OptimizeTNLP(out.nlp);
        out.iterations += out.nlp->iterations;
        if (!out.nlp->finalized) break;
        const Eigen::VectorXd x = out.nlp->x_final.head(sys_.nv());
        bool at_bound = false;
        for (int i = 0; i < bound.size(); ++i)
            if (std::abs(x[i]) >= (1.0 - 1e-4) * bound[i]) at_bound = true;
        const Verdict verdict = judge(x, at_bound, out);
        if (verdict == Verdict::Stop) break;
        if (verdict == Verdict::Shrink) {
            factor_ *= 0.25;  // smaller steps stay on the branch
            ++out.rejected;
            continue;
        }
        accept(x, out);
        ++out.segments;
        if (!at_bound) break;
        if (out.segments >= kMaxSegments) {
            out.failure = "no equilibrium within reach: after " + std::to_string(out.segments) +
                          " re-centred solves the solution still lies on the step box (the " +
                          (potential_ ? "potential keeps decreasing" : "equilibrium keeps receding") +
                          ", e.g. an unsupported body under gravity)";
            break;
        }
        factor_ = std::min(factor_max_, 2.0 * factor_);
    }
    out.factor = factor_;
    return out;
}

Eigen::VectorXd Continuation::box() const {
    Eigen::VectorXd bound;
    if (!trust_) return bound;
    bound.resize(sys_.nv());
    for (int i = 0; i < sys_.nv(); ++i) bound[i] = factor_ * (geo_.rotation(i) ? M_PI / 2 : geo_.length);
    return bound;
}

Continuation::Verdict Continuation::judge(const Eigen::VectorXd& x, bool at_bound, ContinuationResult& out) {
    // an unsuccessful solve only moves the centre when the box stopped it
    // (e.g. virtual work: no equilibrium inside the box is "infeasible")
    const bool stopped_by_box =
        at_bound && (out.status == Ipopt::Infeasible_Problem_Detected || out.status == Ipopt::Restoration_Failed);
    if (!finished(out.status) && !stopped_by_box) return Verdict::Stop;
    q_end_ = out.centre;
    sys_.advance_positions(q_end_, x);
    if (!projector_.project(opt_.time, q_end_, out.ctol)) {
        if (finished(out.status))
            out.failure = "the configuration Ipopt returned cannot be assembled (Newton on C(q) = 0 does not converge)";
        return Verdict::Stop;
    }
    if (sys_.constraint_rows(true) > 0 &&
        !march(sys_, projector_, geo_, opt_.time, out.centre, x, out.ctol).connected) {
        if (trust_ && factor_ > kMinFactor) return Verdict::Shrink;
        out.failure = branch_jump_message(trust_);
        return Verdict::Stop;
    }
    return Verdict::Accept;
}

void Continuation::accept(const Eigen::VectorXd& x, ContinuationResult& out) {
    if (finished(out.status)) sys_.advance_positions(out.centre, x);  // Ipopt's point, not re-projected
    else out.centre = q_end_;
    if (!potential_) tail_ = out.nlp->x_final.tail(out.nlp->x_final.size() - sys_.nv());
}

}  // namespace mbd::ipopt_plugin
