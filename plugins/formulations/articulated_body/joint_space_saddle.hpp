// The saddle-point system of the augmented method written in joint coordinates u (book
// Eq. 6.141 with M -> M_u = H^T M H, J -> Phi_u = J H):
//     [ M_u  Phi_u^T ] [ udot   ]   [ h       ]
//     [ Phi_u  0     ] [ lambda ] = [ gamma_u ]
// solved by the range-space route of the augmented formulation (block inverse, Eqs.
// 6.142-6.145): M_u = L L^T, W = Phi_u L^-T, S = W W^T, S lambda = Phi_u M_u^-1 h - gamma_u,
// udot = M_u^-1 (h - Phi_u^T lambda). S is equilibrated (unit diagonal) and factored by
// Cholesky; a (nearly) rank-deficient S (redundant loop rows, a singular configuration)
// takes the minimum-norm S^+ = (W^T)^+ W^+ from complete orthogonal decompositions of W and
// W^T, whose condition is the square root of S's (as kit dense_gram.hpp does for J M^-1 J^T).
// Left-out rows (structurally redundant) get lambda = 0. Dense: the systems on this path are
// small. Sized once by resize(): factoring and solving allocate nothing after that.
#pragma once

#include <mbd/kit/pseudo_inverse.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace mbd::articulated {

class JointSpaceSaddle {
public:
    void resize(int nu, int nc) {
        Wt_.setZero(nu, nc);
        W_.setZero(nc, nu);
        S_.setZero(nc, nc);
        scale_.setZero(nc);
        w_.setZero(nu);
        x_.setZero(nu);
        skip_.assign(nc, 0);
        llt_M_.compute(Eigen::MatrixXd::Identity(nu, nu));
        if (nc > 0) {  // sizes their storage (see dense_gram.hpp); no rows: nothing to decompose
            llt_S_.compute(Eigen::MatrixXd::Identity(nc, nc));
            cod_w_.compute(W_);
            cod_wt_.compute(Wt_);
        }
        pinv_w_.resize(nc, nu);
        pinv_wt_.resize(nu, nc);
    }
    // rows left out of the solve (lambda = 0)
    void leave_out(const std::vector<int>& rows) {
        std::fill(skip_.begin(), skip_.end(), 0);
        for (int r : rows) skip_[r] = 1;
    }

    // Factors at (M_u, Phi_u). Returns false when M_u is not positive definite. robust: the
    // minimum-norm path without trying Cholesky first.
    bool factor(const Eigen::MatrixXd& Mu, const Eigen::MatrixXd& Phi, bool robust) {
        llt_M_.compute(Mu);
        if (llt_M_.info() != Eigen::Success) return false;
        Wt_ = Phi.transpose();
        robust_ = robust;
        least_relative_pivot_ = 0.0;
        if (S_.rows() == 0) return true;     // no closure rows (Eigen's triangular solve needs storage)
        llt_M_.matrixL().solveInPlace(Wt_);  // W^T = L^-1 Phi^T
        for (int r = 0; r < static_cast<int>(skip_.size()); ++r)
            if (skip_[r]) Wt_.col(r).setZero();
        if (!robust_) {
            S_.noalias() = Wt_.transpose() * Wt_;
            // a row of W that is rounding noise beside the others (a loop's out-of-plane row
            // when its hinges are parallel, ~1e-17) would be scaled up to a unit row by the
            // equilibration, a pivot that looks healthy and a correction that amplifies the
            // row's rounding-level residual by 1e17: such a row is dependent, as for the
            // robust path's threshold (1e-10 of the largest row)
            const double largest = S_.diagonal().maxCoeff();
            bool negligible_row = false;
            for (int r = 0; r < S_.rows(); ++r) {
                const double d = skip_[r] ? 1.0 : S_(r, r);
                negligible_row = negligible_row || (!skip_[r] && !(d > 1e-20 * largest));
                scale_[r] = d > 0.0 ? 1.0 / std::sqrt(d) : 0.0;
                if (skip_[r]) S_(r, r) = 1.0;
            }
            S_ = scale_.asDiagonal() * S_ * scale_.asDiagonal();
            llt_S_.compute(S_);
            if (llt_S_.info() == Eigen::Success && scale_.minCoeff() > 0.0 && !negligible_row) {
                // the least squared diagonal entry of the factor of the unit-diagonal S: the
                // squared sine of the least angle between a row of W and the rows before it
                least_relative_pivot_ = llt_S_.matrixLLT().diagonal().cwiseAbs2().minCoeff();
            }
            robust_ = !(least_relative_pivot_ > 1e-8);
        }
        if (robust_) {
            W_ = Wt_.transpose();
            cod_w_.setThreshold(1e-10);
            cod_wt_.setThreshold(1e-10);
            cod_w_.compute(W_);
            cod_wt_.compute(Wt_);
        }
        return true;
    }
    bool robust() const { return robust_; }
    double least_relative_pivot() const { return robust_ ? 0.0 : least_relative_pivot_; }

    // r <- S^-1 r (S^+ r on the robust path); left-out rows get 0
    void solve_S(Eigen::VectorXd& r) {
        if (r.size() == 0) return;
        for (int k = 0; k < r.size(); ++k)
            if (skip_[k]) r[k] = 0.0;
        if (robust_) {
            pinv_w_.solve(cod_w_, r, w_);   // W^+ r
            pinv_wt_.solve(cod_wt_, w_, r);  // (W^T)^+ W^+ r
        } else {
            r = scale_.asDiagonal() * r;
            llt_S_.solveInPlace(r);
            r = scale_.asDiagonal() * r;
        }
        for (int k = 0; k < r.size(); ++k)
            if (skip_[k]) r[k] = 0.0;
    }
    // x <- M_u^-1 x
    void apply_Mu_inverse(Eigen::VectorXd& x) const { llt_M_.solveInPlace(x); }

    // the block inverse: lambda = S^-1 (Phi M_u^-1 h - g), udot = M_u^-1 (h - Phi^T lambda)
    void solve(const Eigen::MatrixXd& Phi, const Eigen::VectorXd& h, const Eigen::VectorXd& g, Eigen::VectorXd& udot,
               Eigen::VectorXd& lambda) {
        x_ = h;
        apply_Mu_inverse(x_);
        lambda.noalias() = Phi * x_;
        lambda -= g;
        solve_S(lambda);
        udot = h;
        udot.noalias() -= Phi.transpose() * lambda;
        apply_Mu_inverse(udot);
    }
    // x = -M_u^-1 Phi^T S^-1 r: the least-M_u-norm correction with Phi x = -r (projections)
    void correction(const Eigen::MatrixXd& Phi, Eigen::VectorXd& r, Eigen::VectorXd& x) {
        solve_S(r);
        x.noalias() = Phi.transpose() * r;
        x = -x;
        apply_Mu_inverse(x);
    }
    // the factor's W = Phi_u L^-T (its rows' independence in the kinetic-energy metric)
    const Eigen::MatrixXd& Wt() const { return Wt_; }

private:
    Eigen::LLT<Eigen::MatrixXd> llt_M_, llt_S_;
    Eigen::MatrixXd Wt_, W_, S_;
    Eigen::VectorXd scale_, w_, x_;
    std::vector<char> skip_;
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_w_, cod_wt_;
    PseudoInverseSolver pinv_w_, pinv_wt_;
    bool robust_ = false;
    double least_relative_pivot_ = 0.0;
};

}  // namespace mbd::articulated
