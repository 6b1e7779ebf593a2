// M^-1 of the block-diagonal mass matrix, one block per body (planar diag(m, m, J), book
// Eqs. 6.61-6.63; spatial diag(m I, Jbar), Sec. 7.9), with each block's lower Cholesky
// factor Lm (M^-1 = Lm Lm^T). Shared by the formulations that solve with S = J M^-1 J^T
// (augmented, the coordinate projection). Blocks are nvb x nvb (3 planar, 6 spatial), stored
// contiguously body after body: M^-1 x streams 72 bytes a planar body (a 6 x 6 block with the
// 3 x 3 in its corner was 288, spread over three cache lines). The flexible bodies' coordinates
// (System::flexible_coordinates(), after the rigid bodies') form one dense block at the end:
// their constant mass matrices are inverted and factored here, once.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/kit/system.hpp>
#include <mbd/kit/varying_mass.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace mbd {

class BlockMassInverse {
public:
    using Block = Eigen::Map<const Eigen::MatrixXd>;  // a body's nvb x nvb block

    // Throws InputError naming the body whose mass matrix is not positive definite
    // (`who` names the caller in that message).
    void bind(const System& system, const std::string& who) {
        nvb_ = mbd::velocities_per_body(system.dimension());
        const int bodies = system.body_count();
        const Eigen::SparseMatrix<double>& M = system.mass_matrix();
        const size_t block_size = static_cast<size_t>(nvb_) * static_cast<size_t>(nvb_);
        inverse_.assign(block_size * static_cast<size_t>(bodies), 0.0);
        factor_.assign(block_size * static_cast<size_t>(bodies), 0.0);
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
            Eigen::Map<Eigen::MatrixXd>(inverse_.data() + block_size * b, nvb_, nvb_) = inv;
            Eigen::Map<Eigen::MatrixXd>(factor_.data() + block_size * b, nvb_, nvb_) = llt.matrixL();
            const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(inv).eigenvalues();
            least = std::min(least, eigenvalues.minCoeff());
            largest = std::max(largest, eigenvalues.maxCoeff());
        }
        flexible_offset_ = nvb_ * bodies;
        const int flexible = system.flexible_coordinates();
        if (flexible > 0) {
            const Eigen::MatrixXd block = Eigen::MatrixXd(M.block(flexible_offset_, flexible_offset_, flexible, flexible));
            const Eigen::LLT<Eigen::MatrixXd> mass(block);
            flexible_inverse_ = mass.solve(Eigen::MatrixXd::Identity(flexible, flexible));
            flexible_inverse_ = 0.5 * (flexible_inverse_ + flexible_inverse_.transpose()).eval();
            const Eigen::LLT<Eigen::MatrixXd> llt(flexible_inverse_);
            if (mass.info() != Eigen::Success || llt.info() != Eigen::Success || !flexible_inverse_.allFinite())
                throw InputError("", who + ": the mass matrix of the flexible bodies is not positive definite");
            flexible_factor_ = llt.matrixL();
            const Eigen::VectorXd eigenvalues =
                Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(flexible_inverse_).eigenvalues();
            least = std::min(least, eigenvalues.minCoeff());
            largest = std::max(largest, eigenvalues.maxCoeff());
        } else {
            flexible_inverse_.resize(0, 0);
            flexible_factor_.resize(0, 0);
        }
        distortion_ = bodies + flexible > 0 ? std::sqrt(largest / least) : 1.0;
    }
    // Re-inverts and re-factors the blocks of the flexible bodies whose mass matrix varies
    // (kit varying_mass.hpp), from system.mass_matrix() as last updated; the flexible block is
    // block-diagonal by body, and so are its inverse and factor, so the others stay as bound.
    // Throws DynamicsError when such a block is not positive definite there.
    void refresh(const System& system, const std::vector<VaryingMass::Block>& blocks, double t) {
        const Eigen::SparseMatrix<double>& M = system.mass_matrix();
        for (const VaryingMass::Block& b : blocks) {
            const int o = b.offset - flexible_offset_;
            const Eigen::LLT<Eigen::MatrixXd> mass(Eigen::MatrixXd(M.block(b.offset, b.offset, b.size, b.size)));
            Eigen::MatrixXd inverse = mass.solve(Eigen::MatrixXd::Identity(b.size, b.size));
            inverse = 0.5 * (inverse + inverse.transpose()).eval();
            const Eigen::LLT<Eigen::MatrixXd> llt(inverse);
            if (mass.info() != Eigen::Success || llt.info() != Eigen::Success || !inverse.allFinite())
                throw DynamicsError(t, "the mass matrix of flexible body '" + b.name +
                                           "' is not positive definite at this state (with geometric stiffening, "
                                           "a deflection beyond the range of its second-order terms; docs/plugin-sdk.md "
                                           "\"ffrf_body\")");
            flexible_inverse_.block(o, o, b.size, b.size) = inverse;
            flexible_factor_.block(o, o, b.size, b.size) = llt.matrixL();
        }
    }

    // sqrt(cond M): the most that the kinetic-energy metric stretches one direction of
    // velocity space against another
    double distortion() const { return distortion_; }

    int bodies() const { return nvb_ > 0 ? static_cast<int>(inverse_.size()) / (nvb_ * nvb_) : 0; }
    int velocities_per_body() const { return nvb_; }
    Block inverse(int body) const { return Block(inverse_.data() + nvb_ * nvb_ * body, nvb_, nvb_); }
    Block factor(int body) const { return Block(factor_.data() + nvb_ * nvb_ * body, nvb_, nvb_); }  // Lm, lower
    // The flexible bodies' block: its first velocity, its size, M^-1 and its lower factor Lm.
    int flexible_offset() const { return flexible_offset_; }
    int flexible_size() const { return static_cast<int>(flexible_inverse_.rows()); }
    const Eigen::MatrixXd& flexible_inverse() const { return flexible_inverse_; }
    const Eigen::MatrixXd& flexible_factor() const { return flexible_factor_; }

    // out = M^-1 x
    void apply(const Eigen::VectorXd& x, Eigen::VectorXd& out) const {
        if (nvb_ == 3)
            apply_blocks<3>(x, out);
        else
            apply_blocks<6>(x, out);
        if (flexible_size() > 0)
            out.segment(flexible_offset_, flexible_size()).noalias() =
                flexible_inverse_ * x.segment(flexible_offset_, flexible_size());
    }

private:
    template <int N>
    void apply_blocks(const Eigen::VectorXd& x, Eigen::VectorXd& out) const {
        const double* block = inverse_.data();
        for (int b = 0; b < bodies(); ++b, block += N * N)
            out.segment<N>(N * b).noalias() = Eigen::Map<const Eigen::Matrix<double, N, N>>(block) * x.segment<N>(N * b);
    }

    int nvb_ = 3;
    std::vector<double> inverse_, factor_;  // nvb x nvb blocks, column-major, body after body
    double distortion_ = 1.0;
    int flexible_offset_ = 0;
    Eigen::MatrixXd flexible_inverse_, flexible_factor_;  // the flexible bodies' block
};

}  // namespace mbd
