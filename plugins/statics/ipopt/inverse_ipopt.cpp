// Inverse dynamics (plugin kind "inverse", type "ipopt"). See docs/statics.md.
//
// At each time, with the acceleration a prescribed by the drivers:
//     B tau - J_j^T lambda = r,   r = M a - Q,   B = [J_s(1)^T ... J_s(na)^T]
// Premultiplying by a null-space basis Z of J_j (Z^T J_j^T = 0) removes the joint
// multipliers: G tau = h with G = Z^T B, h = Z^T r. Fully actuated: G is square and
// nonsingular, tau is exact (= -lambda_driver of the augmented formulation).
// Redundant: minimum sum w tau^2, the weighted pseudo-inverse solution; when it
// violates a bound, an Ipopt QP (min 1/2 tau^T W tau, G tau = h, lo <= tau <= hi).
// Then lambda from J_j^T lambda = B tau - r (least squares, exact when consistent).
#include "dense_decompositions.hpp"
#include "evaluator.hpp"
#include "ipopt_common.hpp"

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/inverse.hpp>
#include <mbd/sdk/text.hpp>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include <Eigen/Dense>

#include <sstream>

namespace mbd::ipopt_plugin {
namespace {

using Ipopt::Index;
using Ipopt::Number;

// min 1/2 sum w_i tau_i^2  s.t.  G tau = h,  lo <= tau <= hi
class EffortQP : public Ipopt::TNLP {
public:
    EffortQP(const Eigen::MatrixXd& G, const Eigen::VectorXd& h, const Eigen::VectorXd& w, const Eigen::VectorXd& lo,
             const Eigen::VectorXd& hi, const Eigen::VectorXd& start)
        : G_(G), h_(h), w_(w), lo_(lo), hi_(hi), start_(start) {}
    Eigen::VectorXd tau;
    bool done = false;

    bool get_nlp_info(Index& n, Index& m, Index& nj, Index& nh, IndexStyleEnum& style) override {
        n = static_cast<Index>(w_.size());
        m = static_cast<Index>(G_.rows());
        nj = n * m;
        nh = n;
        style = C_STYLE;
        return true;
    }
    bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl, Number* gu) override {
        for (Index i = 0; i < n; ++i) {
            xl[i] = lo_[i] <= -1e299 ? -1e19 : lo_[i];
            xu[i] = hi_[i] >= 1e299 ? 1e19 : hi_[i];
        }
        for (Index i = 0; i < m; ++i) gl[i] = gu[i] = h_[i];
        return true;
    }
    bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
        for (Index i = 0; i < n; ++i) x[i] = start_[i];
        return true;
    }
    bool eval_f(Index n, const Number* x, bool, Number& f) override {
        f = 0;
        for (Index i = 0; i < n; ++i) f += 0.5 * w_[i] * x[i] * x[i];
        return true;
    }
    bool eval_grad_f(Index n, const Number* x, bool, Number* g) override {
        for (Index i = 0; i < n; ++i) g[i] = w_[i] * x[i];
        return true;
    }
    bool eval_g(Index n, const Number* x, bool, Index m, Number* g) override {
        const Eigen::VectorXd v = G_ * Eigen::Map<const Eigen::VectorXd>(x, n);
        for (Index i = 0; i < m; ++i) g[i] = v[i];
        return true;
    }
    bool eval_jac_g(Index n, const Number*, bool, Index m, Index, Index* r, Index* c, Number* v) override {
        Index e = 0;
        for (Index i = 0; i < m; ++i)
            for (Index j = 0; j < n; ++j, ++e) {
                if (v) v[e] = G_(i, j);
                else { r[e] = i; c[e] = j; }
            }
        return true;
    }
    bool eval_h(Index n, const Number*, bool, Number sigma, Index, const Number*, bool, Index, Index* r, Index* c,
                Number* v) override {
        for (Index i = 0; i < n; ++i) {
            if (v) v[i] = sigma * w_[i];
            else { r[i] = i; c[i] = i; }
        }
        return true;
    }
    void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*, const Number*, Index,
                           const Number*, const Number*, Number, const Ipopt::IpoptData*,
                           Ipopt::IpoptCalculatedQuantities*) override {
        tau = Eigen::Map<const Eigen::VectorXd>(x, n);
        done = true;
    }

private:
    Eigen::MatrixXd G_;
    Eigen::VectorXd h_, w_, lo_, hi_, start_;
};

class IpoptInverse final : public InverseSolver {
public:
    void bind(System& system, const InverseOptions& options) override {
        sys_ = &system;
        opt_ = options;
        if (opt_.actuators.empty())
            throw std::invalid_argument("inverse dynamics needs at least one actuator (scene key 'actuators')");
        std::vector<int> joints;
        for (const auto& a : opt_.actuators) joints.push_back(a.joint);
        ev_ = std::make_unique<Evaluator>(system, 0.0, joints);
    }

    InverseSample solve(const State& state, const Eigen::VectorXd& acceleration) override {
        const double t = state.t;
        InverseSample out;
        out.state = state;
        out.acceleration = acceleration;
        ConstraintValues all;
        sys_->constraints(state, all, true);
        require_prescribed_motion(all, acceleration, t);
        EffortEquations eq = effort_equations(state, acceleration, all);
        int rank_g = 0;
        Eigen::VectorXd tau = minimum_effort(eq, t, rank_g);
        const bool unique = rank_g == static_cast<int>(opt_.actuators.size());
        out.method = unique ? "exact" : "pseudo-inverse";
        if (respect_bounds(eq, rank_g, unique, t, tau)) {
            out.method = "qp";
            out.bounds_active = true;
        }
        out.efforts = tau;
        out.lambda = joint_multipliers(eq, tau, t);
        return out;
    }

private:
    // The equations of the efforts, B tau - J_j^T lambda = r, and their reduction to the
    // motion the joints allow, G0 tau = h0 (G0 = Z^T B, h0 = Z^T r, Z a basis of ker J_j).
    struct EffortEquations {
        Eigen::MatrixXd B, Jj, G0;
        Eigen::VectorXd r, h0;
        Eigen::VectorXd w, lo, hi;  // actuator weights and bounds
        double scale = 1.0;         // 1 + max |r| + max |B| |tau| once tau is known
    };

    // The drivers must prescribe the motion, and the acceleration must satisfy them.
    void require_prescribed_motion(const ConstraintValues& all, const Eigen::VectorXd& acceleration, double t) const {
        const int nv = sys_->nv();
        int rank = 0;
        null_space(Eigen::MatrixXd(all.J), nv, rank, 1e-10);
        if (rank < nv) {
            throw DynamicsError(t, "the drivers do not prescribe the motion at t = " + format_time(t) + ": " +
                                       std::to_string(nv - rank) +
                                       " degree(s) of freedom are free; add drivers so that the motion is "
                                       "fully prescribed (kinematically driven)");
        }
        const Eigen::VectorXd ra = Eigen::MatrixXd(all.J) * acceleration - all.gamma;
        if (ra.size() && ra.cwiseAbs().maxCoeff() > 1e-6 * (1.0 + all.gamma.cwiseAbs().maxCoeff()))
            throw DynamicsError(t, "the prescribed acceleration is inconsistent with the drivers at t = " +
                                       format_time(t));
    }

    EffortEquations effort_equations(const State& state, const Eigen::VectorXd& acceleration,
                                     const ConstraintValues& all) {
        System& sys = *sys_;
        const int nv = sys.nv(), mj = sys.constraint_rows(false), na = static_cast<int>(opt_.actuators.size());
        EffortEquations eq;
        Eigen::VectorXd Q;
        sys.generalized_forces(state, Q);
        eq.r = sys.mass_matrix() * acceleration - Q;
        eq.Jj = Eigen::MatrixXd(all.J).topRows(mj);
        eq.B = Eigen::MatrixXd::Zero(nv, na);
        for (int a = 0; a < na; ++a) {
            const Coordinate c = ev_->coordinate(opt_.actuators[a].joint, state.q);
            for (const auto& e : c.grad) eq.B(e.first, a) += e.second;
        }
        int rank_j = 0;
        const Eigen::MatrixXd Z = null_space(eq.Jj, nv, rank_j, 1e-10);
        eq.G0 = Z.transpose() * eq.B;
        eq.h0 = Z.transpose() * eq.r;
        eq.w.resize(na);
        eq.lo.resize(na);
        eq.hi.resize(na);
        for (int a = 0; a < na; ++a) {
            eq.w[a] = opt_.actuators[a].weight;
            eq.lo[a] = opt_.actuators[a].lo;
            eq.hi[a] = opt_.actuators[a].hi;
        }
        return eq;
    }

    // Minimum sum w tau^2 subject to G0 tau = h0 (the weighted pseudo-inverse; rows of
    // G0 may be dependent); throws when the actuators cannot produce the motion.
    Eigen::VectorXd minimum_effort(EffortEquations& eq, double t, int& rank_g) const {
        const int na = static_cast<int>(eq.w.size());
        const Eigen::VectorXd winv_sqrt = eq.w.cwiseSqrt().cwiseInverse();
        const Eigen::MatrixXd Gw = eq.G0 * winv_sqrt.asDiagonal();
        Eigen::VectorXd tau = Eigen::VectorXd::Zero(na);
        rank_g = 0;
        if (eq.G0.rows() > 0) {
            Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Gw);
            cod.setThreshold(1e-10);
            tau = winv_sqrt.asDiagonal() * cod.solve(eq.h0);
            rank_g = static_cast<int>(cod.rank());
        }
        eq.scale = 1.0 + eq.r.cwiseAbs().maxCoeff() + (eq.B.cwiseAbs() * tau.cwiseAbs()).maxCoeff();
        const double consistency = eq.G0.rows() ? (eq.G0 * tau - eq.h0).cwiseAbs().maxCoeff() : 0.0;
        if (consistency > 1e-8 * eq.scale)
            throw DynamicsError(t, "the actuators cannot produce the prescribed motion at t = " + format_time(t) + ": " +
                                       std::to_string(eq.G0.rows()) + " degree(s) of freedom but the actuators span " +
                                       std::to_string(rank_g) + " (under-actuated; residual " +
                                       format_number(consistency) + ")");
        return tau;
    }

    // When tau violates an actuator bound: the bounded QP on the independent rows of
    // G0 (true), or an error when the efforts are unique or the bounds cannot be met.
    bool respect_bounds(const EffortEquations& eq, int rank_g, bool unique, double t, Eigen::VectorXd& tau) const {
        const int na = static_cast<int>(tau.size());
        int worst = -1;
        double excess = 0.0;
        for (int a = 0; a < na; ++a) {
            const double e = std::max(eq.lo[a] - tau[a], tau[a] - eq.hi[a]);
            if (e > excess + 1e-12 * (1.0 + std::abs(tau[a]))) {
                excess = e;
                worst = a;
            }
        }
        if (worst < 0) return false;
        const auto& act = opt_.actuators[worst];
        if (unique)
            throw DynamicsError(t, "actuator '" + act.name + "' needs an effort of " + format_number(tau[worst]) +
                                       " at t = " + format_time(t) + ", outside its bounds [" + format_number(act.lo) +
                                       ", " + format_number(act.hi) + "] (the efforts are unique: fully actuated)");
        // reduce to independent rows, then the bounded QP
        const Eigen::MatrixXd U = singular_value_decomposition(eq.G0, false, 1e-10).U.leftCols(rank_g);
        const Eigen::MatrixXd G = U.transpose() * eq.G0;
        const Eigen::VectorXd h = U.transpose() * eq.h0;
        Ipopt::SmartPtr<EffortQP> qp = new EffortQP(G, h, eq.w, eq.lo, eq.hi, tau.cwiseMax(eq.lo).cwiseMin(eq.hi));
        std::unique_lock<std::mutex> one_ipopt_at_a_time(ipopt_lock());
        Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
        app->Options()->SetIntegerValue("print_level", opt_.print_level);
        app->Options()->SetStringValue("sb", "yes");
        app->Options()->SetNumericValue("tol", 1e-12);
        app->Options()->SetNumericValue("constr_viol_tol", 1e-10 * eq.scale);
        app->Options()->SetStringValue("mehrotra_algorithm", "yes");
        app->Options()->SetStringValue("hessian_constant", "yes");
        app->Options()->SetStringValue("jac_c_constant", "yes");
        app->Initialize();
        const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(qp);
        app = nullptr;  // Ipopt is done: let other threads use it
        one_ipopt_at_a_time.unlock();
        if (!succeeded(status) || !qp->done) {
            std::string names;
            for (int a = 0; a < na; ++a)
                names += (a ? ", " : "") + opt_.actuators[a].name + " [" + format_number(eq.lo[a]) + ", " +
                         format_number(eq.hi[a]) + "]";
            throw DynamicsError(t, "the actuator bounds cannot be met at t = " + format_time(t) + " (Ipopt: " +
                                       status_name(status) + "); the minimum-effort solution needs '" + act.name +
                                       "' = " + format_number(tau[worst]) + "; bounds: " + names);
        }
        tau = qp->tau;
        return true;
    }

    // Joint multipliers from J_j^T lambda = B tau - r (least squares, exact when consistent).
    Eigen::VectorXd joint_multipliers(const EffortEquations& eq, const Eigen::VectorXd& tau, double t) const {
        const Eigen::VectorXd rhs = eq.B * tau - eq.r;
        if (eq.Jj.rows() > 0) {
            Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(eq.Jj.transpose());
            const Eigen::VectorXd lambda = cod.solve(rhs);
            const double res = (eq.Jj.transpose() * lambda - rhs).cwiseAbs().maxCoeff();
            if (res > 1e-7 * eq.scale)
                throw DynamicsError(t, "inverse dynamics: the equations of motion are not satisfied at t = " +
                                           format_time(t) + " (residual " + format_number(res) + ")");
            return lambda;
        }
        if (rhs.cwiseAbs().maxCoeff() > 1e-7 * eq.scale)
            throw DynamicsError(t, "inverse dynamics: the equations of motion are not satisfied at t = " +
                                       format_time(t));
        return Eigen::VectorXd();
    }

    System* sys_ = nullptr;
    InverseOptions opt_;
    std::unique_ptr<Evaluator> ev_;
};

std::unique_ptr<InverseSolver> make_ipopt_inverse(const InverseSpec&) { return std::make_unique<IpoptInverse>(); }

}  // namespace
}  // namespace mbd::ipopt_plugin

MBD_INVERSE_PLUGIN(ipopt, mbd::ipopt_plugin::make_ipopt_inverse)
