// The Ipopt NLP of a statics solve (docs/statics.md), over position increments x
// (q = q0 (+) x) inside an optional box |x_i| <= x_bound[i]:
//  potential    min V(q)  s.t. C(q) = 0, lo <= s_k(q) <= hi       (all forces conservative at rest)
//               Ipopt's multipliers are the Lagrange multipliers: -Q + J^T lambda + J_s^T nu = 0.
//               Hessian: exact (-dQ/dq from the force elements, constraint curvature
//               sum lambda_i d2C_i by coloured central differences of J^T lambda), or L-BFGS.
//  virtual-work unknowns (x, lambda, mu_lo, mu_hi): C(q) = 0, Q - J^T lambda - J_s^T (mu_hi - mu_lo) = 0,
//               lo <= s_k <= hi, mu >= 0, objective sum mu_lo (s - lo) + mu_hi (hi - s) (complementarity,
//               zero at a solution). Without limits this is a square system solved by Newton steps.
//               Hessian: limited-memory.
// Derivatives in x are those in v times T (the right Jacobians of the rotation increments).
#pragma once

#include "evaluator.hpp"

#include <IpIpoptData.hpp>
#include <IpTNLP.hpp>

#include <Eigen/Sparse>

#include <string>
#include <vector>

namespace mbd::ipopt_plugin {

class StaticsNLP : public Ipopt::TNLP {
public:
    using Index = Ipopt::Index;
    using Number = Ipopt::Number;

    // x_bound: the trust region |x_i| <= x_bound[i] around q0 (empty: unbounded).
    // tail0: starting values of the unknowns after x (virtual-work: lambda, mu_lo, mu_hi).
    StaticsNLP(Evaluator& ev, const Eigen::VectorXd& q0, const std::vector<JointLimit>& limits, bool potential,
               bool exact_hessian, const Eigen::VectorXd& tail0, const Eigen::VectorXd& x_bound);

    // results
    Ipopt::SolverReturn solver_status = Ipopt::UNASSIGNED;
    int iterations = 0;
    Eigen::VectorXd x_final, g_multipliers;
    bool finalized = false;
    std::string callback_error;

    bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) override;
    bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override;
    bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index, bool init_lambda,
                            Number*) override;
    bool eval_f(Index n, const Number* x, bool new_x, Number& obj) override;
    bool eval_grad_f(Index n, const Number* x, bool new_x, Number* grad) override;
    bool eval_g(Index, const Number* x, bool new_x, Index m, Number* g) override;
    bool eval_jac_g(Index, const Number* x, bool new_x, Index, Index nele, Index* iRow, Index* jCol,
                    Number* values) override;
    bool eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda, bool, Index nele,
                Index* iRow, Index* jCol, Number* values) override;
    void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number*, const Number*, Index m,
                           const Number*, const Number* lambda, Number, const Ipopt::IpoptData* ip_data,
                           Ipopt::IpoptCalculatedQuantities*) override;

private:
    // Runs an evaluation; an exception becomes `false` for Ipopt and its message is kept.
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

    void update(const Number* x, bool new_x);
    Eigen::VectorXd lambda_of(const Number* x) const { return Eigen::Map<const Eigen::VectorXd>(x + nv_, mc_); }
    Eigen::VectorXd nu_of(const Number* x) const;
    Eigen::VectorXd residual_vector(const Number* x) const;

    // Constraint row r of J and coordinate row k of J_s over their bodies' columns, raw and times T.
    std::vector<double> raw_constraint_row(int r) const;
    std::vector<double> constraint_row(int r) const;
    std::vector<double> raw_coordinate_row(int k) const;
    std::vector<double> coordinate_row(int k) const;
    std::vector<double> times_T(const std::vector<int>& bodies, std::vector<double> row) const;
    int row_position(const std::vector<int>& bodies, int column) const;
    Eigen::MatrixXd right_T(const Eigen::MatrixXd& B, int body) const;
    Eigen::MatrixXd left_T(const Eigen::MatrixXd& B, int body) const;

    Evaluator& ev_;
    Eigen::VectorXd q0_;
    std::vector<JointLimit> limits_;
    bool potential_, exact_;
    int nv_, mc_, nl_;
    Eigen::VectorXd lambda0_, x_bound_;
    int n_ = 0, m_ = 0, off_s_ = 0, ncj_ = 0, nsj_ = 0, nblock_ = 0, nh_ = 0;
    // cache at the current x
    bool have_ = false;
    Eigen::VectorXd q_, Q_;
    ConstraintValues cv_;
    Eigen::SparseMatrix<double, Eigen::RowMajor> Jrow_;
    std::vector<Coordinate> s_;
};

}  // namespace mbd::ipopt_plugin
