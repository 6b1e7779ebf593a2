// Statics with Ipopt (plugin kind "statics", type "ipopt"). See docs/statics.md.
//
// Two nonlinear programs over position increments x (q = q0 (+) x):
//  potential    min V(q)  s.t. C(q) = 0, lo <= s_k(q) <= hi       (all forces conservative at rest)
//               Ipopt's multipliers are the Lagrange multipliers: -Q + J^T lambda + J_s^T nu = 0.
//               Hessian: exact (-dQ/dq from the force elements, constraint curvature
//               sum lambda_i d2C_i by coloured central differences of J^T lambda), or L-BFGS.
//  virtual-work unknowns (x, lambda, mu_lo, mu_hi): C(q) = 0, Q - J^T lambda - J_s^T (mu_hi - mu_lo) = 0,
//               lo <= s_k <= hi, mu >= 0, objective sum mu_lo (s - lo) + mu_hi (hi - s) (complementarity,
//               zero at a solution). Without limits this is a square system solved by Newton steps.
//               Hessian: limited-memory.
#include "evaluator.hpp"
#include "ipopt_common.hpp"

#include <mbd/sdk/statics.hpp>

#include <IpIpoptApplication.hpp>
#include <IpIpoptData.hpp>
#include <IpTNLP.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <cstdlib>
#include <random>
#include <sstream>

namespace mbd::ipopt_plugin {
namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr double kInf = 1e19;

class StaticsNLP : public Ipopt::TNLP {
public:
    StaticsNLP(Evaluator& ev, const Eigen::VectorXd& q0, const std::vector<JointLimit>& limits, bool potential,
               bool exact_hessian, const Eigen::VectorXd& lambda0)
        : ev_(ev), q0_(q0), limits_(limits), potential_(potential), exact_(exact_hessian && potential),
          nv_(ev.nv), mc_(ev.mc), nl_(static_cast<int>(limits.size())), vpb_(ev.vpb), lambda0_(lambda0) {
        n_ = potential_ ? nv_ : nv_ + mc_ + 2 * nl_;
        m_ = potential_ ? mc_ + nl_ : mc_ + nv_ + nl_;
        off_s_ = potential_ ? mc_ : mc_ + nv_;
        for (const auto& rb : ev_.row_bodies) ncj_ += static_cast<int>(rb.size()) * vpb_;
        for (const auto& cb : ev_.coordinate_bodies) nsj_ += static_cast<int>(cb.size()) * vpb_;
        for (int a = 0; a < ev_.nb; ++a) {
            nblock_ += static_cast<int>(ev_.adjacency[a].size()) * vpb_ * vpb_;
            for (int b : ev_.adjacency[a]) {
                if (b < a) nh_ += vpb_ * vpb_;
                if (b == a) nh_ += vpb_ * (vpb_ + 1) / 2;
            }
        }
    }

    // results
    Ipopt::SolverReturn solver_status = Ipopt::UNASSIGNED;
    int iterations = 0;
    Eigen::VectorXd x_final, g_multipliers;
    bool finalized = false;

    bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) override {
        n = n_;
        m = m_;
        nnz_jac_g = ncj_ + nsj_ + (potential_ ? 0 : nblock_ + ncj_ + 2 * nsj_);
        nnz_h_lag = exact_ ? nh_ : 0;
        style = C_STYLE;
        return true;
    }

    bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
        for (Index i = 0; i < n; ++i) {
            x_l[i] = -kInf;
            x_u[i] = kInf;
        }
        if (!potential_)
            for (int k = 0; k < 2 * nl_; ++k) x_l[nv_ + mc_ + k] = 0.0;
        for (Index i = 0; i < m; ++i) g_l[i] = g_u[i] = 0.0;
        for (int k = 0; k < nl_; ++k) {
            g_l[off_s_ + k] = limits_[k].lo;
            g_u[off_s_ + k] = limits_[k].hi;
        }
        return true;
    }

    bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index, bool init_lambda,
                            Number*) override {
        if (init_z || init_lambda) return false;
        if (init_x) {
            for (Index i = 0; i < n; ++i) x[i] = 0.0;
            if (!potential_)
                for (int r = 0; r < mc_ && r < lambda0_.size(); ++r) x[nv_ + r] = lambda0_[r];
        }
        return true;
    }

    bool eval_f(Index n, const Number* x, bool new_x, Number& obj) override {
        return guard([&] {
            update(x, new_x);
            if (potential_) {
                obj = ev_.sys.potential_energy(ev_.state(q_));
            } else {
                obj = 0.0;
                for (int k = 0; k < nl_; ++k)
                    obj += x[nv_ + mc_ + k] * (s_[k].value - limits_[k].lo) + x[nv_ + mc_ + nl_ + k] * (limits_[k].hi - s_[k].value);
            }
            (void)n;
        });
    }

    bool eval_grad_f(Index n, const Number* x, bool new_x, Number* grad) override {
        return guard([&] {
            update(x, new_x);
            for (Index i = 0; i < n; ++i) grad[i] = 0.0;
            if (potential_) {
                for (int b = 0; b < ev_.nb; ++b) {
                    Eigen::Matrix<double, 6, 1> row;
                    for (int c = 0; c < vpb_; ++c) row[c] = -Q_[b * vpb_ + c];
                    ev_.times_T(b, row.data());
                    for (int c = 0; c < vpb_; ++c) grad[b * vpb_ + c] = row[c];
                }
            } else {
                for (int k = 0; k < nl_; ++k) {
                    const double w = x[nv_ + mc_ + k] - x[nv_ + mc_ + nl_ + k];
                    const std::vector<double> row = coordinate_row(k);
                    const auto& bodies = ev_.coordinate_bodies[k];
                    for (size_t p = 0; p < bodies.size(); ++p)
                        for (int c = 0; c < vpb_; ++c) grad[bodies[p] * vpb_ + c] += w * row[p * vpb_ + c];
                    grad[nv_ + mc_ + k] = s_[k].value - limits_[k].lo;
                    grad[nv_ + mc_ + nl_ + k] = limits_[k].hi - s_[k].value;
                }
            }
        });
    }

    bool eval_g(Index, const Number* x, bool new_x, Index m, Number* g) override {
        return guard([&] {
            update(x, new_x);
            for (Index i = 0; i < m; ++i) g[i] = 0.0;
            for (int r = 0; r < mc_; ++r) g[r] = cv_.C[r];
            if (!potential_) {
                const Eigen::VectorXd R = residual_vector(x);
                for (int i = 0; i < nv_; ++i) g[mc_ + i] = R[i];
            }
            for (int k = 0; k < nl_; ++k) g[off_s_ + k] = s_[k].value;
        });
    }

    bool eval_jac_g(Index, const Number* x, bool new_x, Index, Index nele, Index* iRow, Index* jCol,
                    Number* values) override {
        return guard([&] {
            Index e = 0;
            const bool fill = values != nullptr;
            if (fill) update(x, new_x);
            // C rows: J T
            for (int r = 0; r < mc_; ++r) {
                const auto& bodies = ev_.row_bodies[r];
                std::vector<double> row;
                if (fill) row = constraint_row(r);
                for (size_t p = 0; p < bodies.size(); ++p)
                    for (int c = 0; c < vpb_; ++c, ++e) {
                        if (fill) values[e] = row[p * vpb_ + c];
                        else { iRow[e] = r; jCol[e] = bodies[p] * vpb_ + c; }
                    }
            }
            if (!potential_) {
                // R rows, x columns: (dQ/dq - d(J^T lambda + J_s^T nu)/dq) T
                if (fill) {
                    ev_.clear_blocks();
                    ev_.add_force_jacobian(q_, 1.0);
                    ev_.add_constraint_curvature(q_, lambda_of(x), nu_of(x), -1.0);
                }
                for (int a = 0; a < ev_.nb; ++a)
                    for (size_t k = 0; k < ev_.adjacency[a].size(); ++k) {
                        const int b = ev_.adjacency[a][k];
                        Eigen::MatrixXd B;
                        if (fill) B = right_T(ev_.blocks[a][k], b);
                        for (int i = 0; i < vpb_; ++i)
                            for (int j = 0; j < vpb_; ++j, ++e) {
                                if (fill) values[e] = B(i, j);
                                else { iRow[e] = mc_ + a * vpb_ + i; jCol[e] = b * vpb_ + j; }
                            }
                    }
                // R rows, lambda columns: -J^T
                for (int r = 0; r < mc_; ++r) {
                    const auto& bodies = ev_.row_bodies[r];
                    std::vector<double> row;
                    if (fill) row = raw_constraint_row(r);
                    for (size_t p = 0; p < bodies.size(); ++p)
                        for (int c = 0; c < vpb_; ++c, ++e) {
                            if (fill) values[e] = -row[p * vpb_ + c];
                            else { iRow[e] = mc_ + bodies[p] * vpb_ + c; jCol[e] = nv_ + r; }
                        }
                }
                // R rows, mu columns: +J_s^T (mu_lo), -J_s^T (mu_hi)
                for (int side = 0; side < 2; ++side)
                    for (int k = 0; k < nl_; ++k) {
                        const auto& bodies = ev_.coordinate_bodies[k];
                        std::vector<double> row;
                        if (fill) row = raw_coordinate_row(k);
                        for (size_t p = 0; p < bodies.size(); ++p)
                            for (int c = 0; c < vpb_; ++c, ++e) {
                                if (fill) values[e] = (side == 0 ? 1.0 : -1.0) * row[p * vpb_ + c];
                                else { iRow[e] = mc_ + bodies[p] * vpb_ + c; jCol[e] = nv_ + mc_ + side * nl_ + k; }
                            }
                    }
            }
            // limit rows: J_s T
            for (int k = 0; k < nl_; ++k) {
                const auto& bodies = ev_.coordinate_bodies[k];
                std::vector<double> row;
                if (fill) row = coordinate_row(k);
                for (size_t p = 0; p < bodies.size(); ++p)
                    for (int c = 0; c < vpb_; ++c, ++e) {
                        if (fill) values[e] = row[p * vpb_ + c];
                        else { iRow[e] = off_s_ + k; jCol[e] = bodies[p] * vpb_ + c; }
                    }
            }
            if (e != nele) throw std::logic_error("Jacobian size mismatch");
        });
    }

    bool eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda, bool,
                Index nele, Index* iRow, Index* jCol, Number* values) override {
        if (!exact_) return false;
        return guard([&] {
            const bool fill = values != nullptr;
            if (fill) {
                update(x, new_x);
                ev_.clear_blocks();
                if (obj_factor != 0.0) ev_.add_force_jacobian(q_, -obj_factor);
                Eigen::VectorXd lam = Eigen::Map<const Eigen::VectorXd>(lambda, mc_);
                Eigen::VectorXd nu = Eigen::Map<const Eigen::VectorXd>(lambda + mc_, nl_);
                ev_.add_constraint_curvature(q_, lam, nu, 1.0);
            }
            Index e = 0;
            for (int a = 0; a < ev_.nb; ++a)
                for (size_t k = 0; k < ev_.adjacency[a].size(); ++k) {
                    const int b = ev_.adjacency[a][k];
                    if (b > a) continue;
                    Eigen::MatrixXd S;
                    if (fill) {
                        const Eigen::MatrixXd Hab = left_T(right_T(ev_.blocks[a][k], b), a);
                        const Eigen::MatrixXd Hba = left_T(right_T(ev_.blocks[b][ev_.block_index(b, a)], a), b);
                        S = 0.5 * (Hab + Hba.transpose());
                    }
                    for (int i = 0; i < vpb_; ++i)
                        for (int j = 0; j < vpb_; ++j) {
                            if (b == a && j > i) continue;
                            if (fill) values[e] = S(i, j);
                            else { iRow[e] = a * vpb_ + i; jCol[e] = b * vpb_ + j; }
                            ++e;
                        }
                }
            if (e != nele) throw std::logic_error("Hessian size mismatch");
        });
    }

    void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number*, const Number*, Index m,
                           const Number*, const Number* lambda, Number, const Ipopt::IpoptData* ip_data,
                           Ipopt::IpoptCalculatedQuantities*) override {
        solver_status = status;
        x_final = Eigen::Map<const Eigen::VectorXd>(x, n);
        g_multipliers = Eigen::Map<const Eigen::VectorXd>(lambda, m);
        if (ip_data) iterations = ip_data->iter_count();
        finalized = true;
    }

    std::string callback_error;

private:
    template <class F>
    bool guard(F&& f) {
        try {
            f();
            return true;
        } catch (const std::exception& e) {
            if (callback_error.empty()) callback_error = e.what();
            return false;
        }
    }

    void update(const Number* x, bool new_x) {
        if (!new_x && have_) return;
        const Eigen::VectorXd xv = Eigen::Map<const Eigen::VectorXd>(x, nv_);
        ev_.configure(q0_, xv, q_);
        const State st = ev_.state(q_);
        if (mc_ > 0) {
            ev_.sys.constraints(st, cv_, true);
            Jrow_ = cv_.J;
        } else {
            cv_.C.resize(0);
        }
        ev_.sys.generalized_forces(st, Q_);
        s_.clear();
        for (const auto& l : limits_) s_.push_back(ev_.coordinate(l.joint, q_));
        have_ = true;
    }

    Eigen::VectorXd lambda_of(const Number* x) const { return Eigen::Map<const Eigen::VectorXd>(x + nv_, mc_); }
    Eigen::VectorXd nu_of(const Number* x) const {
        Eigen::VectorXd nu(nl_);
        for (int k = 0; k < nl_; ++k) nu[k] = x[nv_ + mc_ + nl_ + k] - x[nv_ + mc_ + k];
        return nu;
    }
    Eigen::VectorXd residual_vector(const Number* x) const {
        Eigen::VectorXd R = Q_;
        if (mc_ > 0) R -= cv_.J.transpose() * lambda_of(x);
        const Eigen::VectorXd nu = nu_of(x);
        for (int k = 0; k < nl_; ++k)
            for (const auto& e : s_[k].grad) R[e.first] -= e.second * nu[k];
        return R;
    }

    // Constraint row r of J over its bodies' columns, raw and times T.
    std::vector<double> raw_constraint_row(int r) const {
        const auto& bodies = ev_.row_bodies[r];
        std::vector<double> row(bodies.size() * vpb_, 0.0);
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Jrow_, r); it; ++it) {
            const int b = static_cast<int>(it.col()) / vpb_;
            auto pos = std::find(bodies.begin(), bodies.end(), b);
            if (pos != bodies.end()) row[(pos - bodies.begin()) * vpb_ + it.col() % vpb_] = it.value();
        }
        return row;
    }
    std::vector<double> constraint_row(int r) const {
        std::vector<double> row = raw_constraint_row(r);
        const auto& bodies = ev_.row_bodies[r];
        for (size_t p = 0; p < bodies.size(); ++p) ev_.times_T(bodies[p], row.data() + p * vpb_);
        return row;
    }
    std::vector<double> raw_coordinate_row(int k) const {
        const auto& bodies = ev_.coordinate_bodies[k];
        std::vector<double> row(bodies.size() * vpb_, 0.0);
        for (const auto& e : s_[k].grad) {
            auto pos = std::find(bodies.begin(), bodies.end(), e.first / vpb_);
            if (pos != bodies.end()) row[(pos - bodies.begin()) * vpb_ + e.first % vpb_] += e.second;
        }
        return row;
    }
    std::vector<double> coordinate_row(int k) const {
        std::vector<double> row = raw_coordinate_row(k);
        const auto& bodies = ev_.coordinate_bodies[k];
        for (size_t p = 0; p < bodies.size(); ++p) ev_.times_T(bodies[p], row.data() + p * vpb_);
        return row;
    }
    Eigen::MatrixXd right_T(const Eigen::MatrixXd& B, int body) const {
        if (ev_.dim == Dimension::Planar) return B;
        Eigen::MatrixXd out = B;
        out.rightCols<3>() = B.rightCols<3>() * ev_.T[body];
        return out;
    }
    Eigen::MatrixXd left_T(const Eigen::MatrixXd& B, int body) const {
        if (ev_.dim == Dimension::Planar) return B;
        Eigen::MatrixXd out = B;
        out.bottomRows<3>() = ev_.T[body].transpose() * B.bottomRows<3>();
        return out;
    }

    Evaluator& ev_;
    Eigen::VectorXd q0_;
    std::vector<JointLimit> limits_;
    bool potential_, exact_;
    int nv_, mc_, nl_, vpb_;
    Eigen::VectorXd lambda0_;
    int n_ = 0, m_ = 0, off_s_ = 0, ncj_ = 0, nsj_ = 0, nblock_ = 0, nh_ = 0;
    // cache at the current x
    bool have_ = false;
    Eigen::VectorXd q_, Q_;
    ConstraintValues cv_;
    Eigen::SparseMatrix<double, Eigen::RowMajor> Jrow_;
    std::vector<Coordinate> s_;
};

// True when Q(q, v = 0) = -grad V at q0 and at a perturbed configuration (checked
// along a few random directions): the forces are conservative at rest (damping
// does not count), so the potential can be minimised.
bool conservative_at_rest(const System& sys, const State& start) {
    const int nv = sys.nv();
    std::mt19937 rng(12345);
    std::normal_distribution<double> normal;
    auto random_vector = [&] {
        Eigen::VectorXd d(nv);
        for (int i = 0; i < nv; ++i) d[i] = normal(rng);
        return d;
    };
    Eigen::VectorXd Q;
    for (int point = 0; point < 2; ++point) {
        State s = start;
        s.v.setZero(nv);
        if (point == 1) sys.advance_positions(s.q, 1e-2 * random_vector());
        sys.generalized_forces(s, Q);
        for (int trial = 0; trial < 3; ++trial) {
            const Eigen::VectorXd d = random_vector().normalized();
            const double h = 1e-6;
            State p = s, m = s;
            sys.advance_positions(p.q, h * d);
            sys.advance_positions(m.q, -h * d);
            const double dV = (sys.potential_energy(p) - sys.potential_energy(m)) / (2 * h);
            const double work = Q.dot(d);
            if (std::abs(dV + work) > 1e-6 * (std::abs(dV) + Q.norm()) + 1e-9) return false;
        }
    }
    return true;
}

// Minimum-norm least-squares lambda from J^T lambda = Q (starting multipliers).
Eigen::VectorXd initial_multipliers(const System& sys, const State& s) {
    const int mc = sys.constraint_rows(true);
    if (mc == 0) return Eigen::VectorXd();
    ConstraintValues cv;
    sys.constraints(s, cv, true);
    Eigen::VectorXd Q;
    sys.generalized_forces(s, Q);
    if (sys.nv() <= 1500) {
        const Eigen::MatrixXd Jt = Eigen::MatrixXd(cv.J).transpose();
        return Jt.completeOrthogonalDecomposition().solve(Q);
    }
    Eigen::SparseMatrix<double> A = cv.J * cv.J.transpose();
    for (int i = 0; i < mc; ++i) A.coeffRef(i, i) += 1e-12 * (1.0 + A.coeffRef(i, i));
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    return ldlt.solve(cv.J * Q);
}

class IpoptStatics final : public StaticsSolver {
public:
    StaticsResult solve(const System& sys, const State& start, const StaticsOptions& opt) override {
        StaticsResult res;
        res.state = start;
        res.state.t = opt.time;
        res.state.v = Eigen::VectorXd::Zero(sys.nv());
        const int nv = sys.nv(), mc = sys.constraint_rows(true), nl = static_cast<int>(opt.limits.size());

        bool potential;
        if (opt.objective == "potential")
            potential = true;
        else if (opt.objective == "virtual-work")
            potential = false;
        else
            potential = sys.conservative() || conservative_at_rest(sys, res.state);
        res.objective = potential ? "potential" : "virtual-work";

        std::vector<int> limit_joints;
        for (const auto& l : opt.limits) limit_joints.push_back(l.joint);
        Evaluator ev(sys, opt.time, limit_joints);

        Eigen::VectorXd lambda0 = potential ? Eigen::VectorXd() : initial_multipliers(sys, res.state);
        Ipopt::SmartPtr<StaticsNLP> nlp =
            new StaticsNLP(ev, res.state.q, opt.limits, potential, opt.hessian != "limited-memory", lambda0);
        Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
        app->Options()->SetIntegerValue("print_level", opt.print_level);
        app->Options()->SetStringValue("sb", "yes");
        app->Options()->SetNumericValue("tol", opt.tolerance);
        app->Options()->SetNumericValue("constr_viol_tol", opt.tolerance);
        app->Options()->SetNumericValue("dual_inf_tol", opt.tolerance);
        app->Options()->SetNumericValue("compl_inf_tol", std::max(opt.tolerance, 1e-12));
        app->Options()->SetIntegerValue("max_iter", opt.max_iterations);
        app->Options()->SetStringValue("mu_strategy", "adaptive");
        app->Options()->SetStringValue("hessian_approximation",
                                       potential && opt.hessian != "limited-memory" ? "exact" : "limited-memory");
        if (const char* check = std::getenv("MBD_IPOPT_DERIVATIVE_TEST"))  // debugging aid: first-order, second-order
            app->Options()->SetStringValue("derivative_test", check);
        Ipopt::ApplicationReturnStatus status = app->Initialize();
        if (status != Ipopt::Solve_Succeeded) {
            res.status = status_name(status);
            res.message = "Ipopt could not be initialised";
            return res;
        }
        status = app->OptimizeTNLP(nlp);
        res.status = status_name(status);
        res.iterations = nlp->iterations;
        if (!nlp->finalized) {
            res.message = "Ipopt stopped without a result (" + res.status + ")" +
                          (nlp->callback_error.empty() ? std::string() : ": " + nlp->callback_error);
            return res;
        }

        // the equilibrium and its multipliers
        const Eigen::VectorXd x = nlp->x_final.head(nv);
        ev.configure(start.q, x, res.state.q);
        Eigen::VectorXd nu = Eigen::VectorXd::Zero(nl);
        if (potential) {
            res.lambda = nlp->g_multipliers.head(mc);
            nu = nlp->g_multipliers.segment(mc, nl);
        } else {
            res.lambda = nlp->x_final.segment(nv, mc);
            for (int k = 0; k < nl; ++k) nu[k] = nlp->x_final[nv + mc + nl + k] - nlp->x_final[nv + mc + k];
        }
        if (nl > 0 && nv <= 600) polish(sys, ev, res.state, res.lambda, nu, opt.limits);
        res.limit_multipliers = nu;

        // residual of the equilibrium equations
        Eigen::VectorXd Q;
        sys.generalized_forces(res.state, Q);
        Eigen::VectorXd R = Q;
        double c_max = 0.0;
        if (mc > 0) {
            ConstraintValues cv;
            sys.constraints(res.state, cv, true);
            R -= cv.J.transpose() * res.lambda;
            c_max = cv.C.cwiseAbs().maxCoeff();
        }
        double bound_violation = 0.0;
        res.limit_active.assign(nl, false);
        std::vector<int> active;
        for (int k = 0; k < nl; ++k) {
            const Coordinate c = ev.coordinate(opt.limits[k].joint, res.state.q);
            for (const auto& e : c.grad) R[e.first] -= e.second * nu[k];
            bound_violation = std::max({bound_violation, opt.limits[k].lo - c.value, c.value - opt.limits[k].hi});
            const double scale = 1e-7 * (1.0 + std::abs(c.value));
            if (c.value - opt.limits[k].lo < scale || opt.limits[k].hi - c.value < scale) {
                res.limit_active[k] = true;
                active.push_back(k);
            }
        }
        const double r_max = R.size() ? R.cwiseAbs().maxCoeff() : 0.0;
        res.residual = std::max({c_max, r_max, bound_violation});
        const double q_scale = 1.0 + (Q.size() ? Q.cwiseAbs().maxCoeff() : 0.0);
        res.converged = succeeded(status) && res.residual <= 1e-6 * q_scale;
        if (!res.converged) {
            std::ostringstream m;
            if (status == Ipopt::Infeasible_Problem_Detected)
                m << "no configuration satisfies the joints, drivers and limits together (Ipopt: infeasible problem)";
            else if (!succeeded(status))
                m << "Ipopt failed (" << res.status << ") after " << res.iterations << " iterations";
            else
                m << "no equilibrium: Ipopt stopped with residual " << res.residual;
            m << "; max |C| = " << c_max << ", max |Q - J^T lambda| = " << r_max;
            if (bound_violation > 0) m << ", limit violation " << bound_violation;
            if (!nlp->callback_error.empty()) m << "; " << nlp->callback_error;
            res.message = m.str();
            res.stability = "not assessed";
            return res;
        }

        if (opt.analyse_stability)
            stability(sys, ev, res, opt, active);
        else
            res.stability = "not assessed";
        return res;
    }

private:
    // Interior-point iterates stop a barrier distance (~tol / nu) inside an active
    // limit. Newton steps on the square system [C; s_a - bound; Q - J^T lambda -
    // J_a^T nu_a] = 0 (active limits as equalities) put them on it exactly.
    static void polish(const System& sys, Evaluator& ev, State& state, Eigen::VectorXd& lambda, Eigen::VectorXd& nu,
                       const std::vector<JointLimit>& limits) {
        const int nv = sys.nv(), mc = sys.constraint_rows(true);
        std::vector<int> act;
        std::vector<double> bound;
        for (size_t k = 0; k < limits.size(); ++k) {
            const Coordinate c = ev.coordinate(limits[k].joint, state.q);
            const double gap = 1e-6 * (1.0 + std::abs(c.value));
            if (c.value - limits[k].lo < gap) { act.push_back(static_cast<int>(k)); bound.push_back(limits[k].lo); }
            else if (limits[k].hi - c.value < gap) { act.push_back(static_cast<int>(k)); bound.push_back(limits[k].hi); }
        }
        if (act.empty()) return;
        const int na = static_cast<int>(act.size()), n = nv + mc + na;
        for (int it = 0; it < 4; ++it) {
            ConstraintValues cv;
            if (mc > 0) sys.constraints(state, cv, true);
            Eigen::VectorXd Q;
            sys.generalized_forces(state, Q);
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
            Eigen::VectorXd F = Eigen::VectorXd::Zero(n);
            Eigen::VectorXd R = Q;
            if (mc > 0) {
                const Eigen::MatrixXd J(cv.J);
                A.block(0, 0, mc, nv) = J;
                A.block(mc + na, nv, nv, mc) = -J.transpose();
                F.head(mc) = cv.C;
                R -= J.transpose() * lambda;
            }
            for (int a = 0; a < na; ++a) {
                const Coordinate c = ev.coordinate(limits[act[a]].joint, state.q);
                F[mc + a] = c.value - bound[a];
                for (const auto& e : c.grad) {
                    A(mc + a, e.first) += e.second;
                    A(mc + na + e.first, nv + mc + a) -= e.second;
                    R[e.first] -= e.second * nu[act[a]];
                }
            }
            F.tail(nv) = R;
            if (F.cwiseAbs().maxCoeff() < 1e-14 * (1.0 + Q.cwiseAbs().maxCoeff())) break;
            ev.clear_blocks();
            ev.add_force_jacobian(state.q, 1.0);
            ev.add_constraint_curvature(state.q, lambda, nu, -1.0);
            A.block(mc + na, 0, nv, nv) = ev.dense_blocks();
            const Eigen::VectorXd d = A.fullPivLu().solve(-F);
            if (!d.allFinite()) return;
            sys.advance_positions(state.q, d.head(nv));
            if (mc > 0) lambda += d.segment(nv, mc);
            for (int a = 0; a < na; ++a) nu[act[a]] += d[nv + mc + a];
        }
    }

    // Reduced Hessian of the potential on the tangent space of the active constraints:
    // K = sym(-dQ/dq) + sym(d(J^T lambda + J_s^T nu)/dq), Z^T K Z with Z a null-space basis.
    static void stability(const System& sys, Evaluator& ev, StaticsResult& res, const StaticsOptions& opt,
                          const std::vector<int>& active) {
        const int nv = sys.nv(), mc = sys.constraint_rows(true);
        ev.clear_blocks();
        ev.add_force_jacobian(res.state.q, -1.0);
        ev.add_constraint_curvature(res.state.q, res.lambda, res.limit_multipliers, 1.0);
        ConstraintValues cv;
        if (mc > 0) sys.constraints(res.state, cv, true);
        std::vector<Coordinate> rows;
        for (int k : active) rows.push_back(ev.coordinate(opt.limits[k].joint, res.state.q));
        const int ma = mc + static_cast<int>(rows.size());

        if (nv <= 600) {
            Eigen::MatrixXd K = ev.dense_blocks();
            K = 0.5 * (K + K.transpose()).eval();
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(ma, nv);
            if (mc > 0) A.topRows(mc) = Eigen::MatrixXd(cv.J);
            for (size_t k = 0; k < rows.size(); ++k)
                for (const auto& e : rows[k].grad) A(mc + k, e.first) += e.second;
            Eigen::MatrixXd Z;
            if (ma == 0) {
                Z = Eigen::MatrixXd::Identity(nv, nv);
            } else {
                Eigen::BDCSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
                const Eigen::VectorXd& s = svd.singularValues();
                int rank = 0;
                for (int i = 0; i < s.size(); ++i)
                    if (s[i] > 1e-9 * std::max(1.0, s[0])) ++rank;
                Z = svd.matrixV().rightCols(nv - rank);
            }
            res.tangent_dimension = static_cast<int>(Z.cols());
            if (Z.cols() == 0) {
                res.stability = "stable";  // fully constrained: no motion possible
                res.tangent_eigenvalues.resize(0);
                return;
            }
            const Eigen::MatrixXd H = Z.transpose() * K * Z;
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (H + H.transpose()));
            res.tangent_eigenvalues = eig.eigenvalues();
            const double scale = std::max(1.0, K.cwiseAbs().maxCoeff());
            const double tol = opt.stability_tolerance * scale;
            if (res.tangent_eigenvalues.minCoeff() < -tol)
                res.stability = "unstable";
            else if (res.tangent_eigenvalues.minCoeff() > tol)
                res.stability = "stable";
            else
                res.stability = "neutral";
            return;
        }

        // Large systems: inertia of K + rho A^T A (Finsler), sparse LDL^T.
        Eigen::SparseMatrix<double> K = ev.sparse_blocks();
        K = 0.5 * (Eigen::SparseMatrix<double>(K.transpose()) + K);
        std::vector<Eigen::Triplet<double>> t;
        if (mc > 0)
            for (int c = 0; c < cv.J.outerSize(); ++c)
                for (Eigen::SparseMatrix<double>::InnerIterator it(cv.J, c); it; ++it)
                    t.emplace_back(it.row(), it.col(), it.value());
        for (size_t k = 0; k < rows.size(); ++k)
            for (const auto& e : rows[k].grad) t.emplace_back(mc + k, e.first, e.second);
        Eigen::SparseMatrix<double> A(ma, nv);
        A.setFromTriplets(t.begin(), t.end());
        double kmax = 1.0, amax = 1e-300;
        for (int c = 0; c < K.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) kmax = std::max(kmax, std::abs(it.value()));
        for (int c = 0; c < A.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) amax = std::max(amax, std::abs(it.value()));
        const double rho = 1e6 * kmax / (amax * amax);
        Eigen::SparseMatrix<double> P = K + rho * Eigen::SparseMatrix<double>(A.transpose() * A);
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(P);
        res.tangent_dimension = -1;
        if (ldlt.info() != Eigen::Success) {
            res.stability = "neutral";
            return;
        }
        const Eigen::VectorXd D = ldlt.vectorD();
        const double tol = opt.stability_tolerance * kmax;
        if (D.minCoeff() < -tol)
            res.stability = "unstable";
        else if (D.minCoeff() > tol)
            res.stability = "stable";
        else
            res.stability = "neutral";
    }
};

std::unique_ptr<StaticsSolver> make_ipopt_statics(const StaticsSpec&) { return std::make_unique<IpoptStatics>(); }

}  // namespace
}  // namespace mbd::ipopt_plugin

MBD_STATICS_PLUGIN(ipopt, mbd::ipopt_plugin::make_ipopt_statics)
