// A sparse S = J M^-1 J^T solver for project_onto_constraints (kit projection.hpp), the sparse
// counterpart of its DenseMetricSolver with the same interface: S = W W^T, W = J Lm, on W's
// fixed pattern (sparse_gram.hpp: ordered once, factored L D L^T without allocation); when S is
// (nearly) singular, damped least squares W W^T + 1e-12 max diag(S) I with two refinements, as
// the augmented formulation's sparse path.
#pragma once

#include <mbd/kit/sparse_gram.hpp>

#include <mbd/kit/block_mass_inverse.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>

namespace mbd {

class SparseMetricSolver {
public:
    void bind(System& system) {
        mass_inverse_.bind(system, "coordinate projection");
        if (system.constraint_rows(true) > 0) gram_.analyze(system);
    }
    void apply_Minv(const Eigen::VectorXd& x, Eigen::VectorXd& out) const { mass_inverse_.apply(x, out); }
    void factor(const Eigen::SparseMatrix<double>& J, bool robust) {
        if (J.rows() == 0) return;
        gram_.fill(J, mass_inverse_);
        damped_ = robust || !gram_.factor(0.0);
        if (damped_) gram_.factor(1e-12 * std::max(gram_.max_diagonal(), 1e-300));
    }
    void solve(Eigen::VectorXd& x) {
        if (x.size() > 0) gram_.solve(x, damped_ ? 2 : 0);
    }
    double least_relative_pivot() const { return damped_ ? 0.0 : gram_.least_relative_pivot(); }
    double metric_distortion() const { return mass_inverse_.distortion(); }

private:
    BlockMassInverse mass_inverse_;
    SparseGram gram_;
    bool damped_ = false;
};

}  // namespace mbd
