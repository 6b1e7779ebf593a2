// M^-1 of the block-diagonal mass matrix, one block per body (planar diag(m, m, J), book
// Eqs. 6.61-6.63; spatial diag(m I, Jbar), Sec. 7.9), with each block's lower Cholesky
// factor Lm (M^-1 = Lm Lm^T). Shared by the formulations that solve with S = J M^-1 J^T
// (augmented, the coordinate projection). Blocks are 6 x 6; a planar body's 3 x 3 block
// sits in the top-left corner with zeros elsewhere, so a 6-wide product is also right.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/sdk/system.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace mbd {

class BlockMassInverse {
public:
    using Block = Eigen::Matrix<double, 6, 6>;

    // Throws InputError naming the body whose mass matrix is not positive definite
    // (`who` names the caller in that message).
    void bind(const System& system, const std::string& who) {
        nvb_ = mbd::velocities_per_body(system.dimension());
        const int bodies = system.body_count();
        const Eigen::SparseMatrix<double>& M = system.mass_matrix();
        inverse_.assign(bodies, Block::Zero());
        factor_.assign(bodies, Block::Zero());
        double least = std::numeric_limits<double>::infinity(), largest = 0.0;
        for (int b = 0; b < bodies; ++b) {
            const int o = b * nvb_;
            const Eigen::MatrixXd block = Eigen::MatrixXd(M.block(o, o, nvb_, nvb_));
            Eigen::MatrixXd inv = block.inverse();
            inv = 0.5 * (inv + inv.transpose());
            const Eigen::LLT<Eigen::MatrixXd> llt(inv);
            if (llt.info() != Eigen::Success || !inv.allFinite())
                throw InputError("", who + ": the mass matrix of body '" + system.body(b).name +
                                         "' is not positive definite");
            inverse_[b].topLeftCorner(nvb_, nvb_) = inv;
            factor_[b].topLeftCorner(nvb_, nvb_) = llt.matrixL();
            const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(inv).eigenvalues();
            least = std::min(least, eigenvalues.minCoeff());
            largest = std::max(largest, eigenvalues.maxCoeff());
        }
        distortion_ = bodies > 0 ? std::sqrt(largest / least) : 1.0;
    }
    // sqrt(cond M): the most that the kinetic-energy metric stretches one direction of
    // velocity space against another
    double distortion() const { return distortion_; }

    int bodies() const { return static_cast<int>(inverse_.size()); }
    int velocities_per_body() const { return nvb_; }
    const Block& inverse(int body) const { return inverse_[body]; }
    const Block& factor(int body) const { return factor_[body]; }  // Lm, lower

    // out = M^-1 x
    void apply(const Eigen::VectorXd& x, Eigen::VectorXd& out) const {
        if (nvb_ == 3) {
            for (int b = 0; b < bodies(); ++b)
                out.segment<3>(3 * b).noalias() = inverse_[b].topLeftCorner<3, 3>() * x.segment<3>(3 * b);
        } else {
            for (int b = 0; b < bodies(); ++b)
                out.segment<6>(6 * b).noalias() = inverse_[b] * x.segment<6>(6 * b);
        }
    }

private:
    int nvb_ = 3;
    std::vector<Block> inverse_, factor_;
    double distortion_ = 1.0;
};

}  // namespace mbd
