// Cyclic directions of a linearised model (issue 42): the position directions that the
// equations of motion do not depend on, a position on the ground, a heading, a wheel's spin
// angle. Internal to the core: linearisation.cpp finds them (the linear search below, each
// direction then confirmed on the nonlinear equations) and modes.cpp sets them apart.
//
// Why not by the eigenvalues: a zero eigenvalue also comes from a mode that only happens to
// be neutral (a bicycle's capsize mode at its critical speed, a rolling disc's steady turn), and
// an eigenvalue near zero is not zero. A direction is cyclic when the equations show it: a
// position increment along it changes no acceleration and no position rate outside the set.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace mbd {

// A shift of the positions carries the velocities along: each spatial body keeps its
// angular velocity in its own axes (a wheel shifted in heading spins about its new axle),
// so the independent velocities w (in the reference axes, linearisation.hpp) change by
// `carried` (k_w x k_z) times the shift, to first order. The largest subspace S of
// span(within) (within: k_z x m) of position directions whose shifts (d, carried d) change
// no rate outside the shifts of S: A [S; carried S] within span [S; carried S], A the
// (k_z + k_w) square state matrix; singular values at most `tolerance` count as zero. An
// orthonormal basis (k_z x s). The descending iteration S_0 = span(within),
// S_(j+1) = {s in S_j : A s in S_j} ends at the largest such subspace.
Eigen::MatrixXd invariant_position_subspace(const Eigen::MatrixXd& A, const Eigen::MatrixXd& carried,
                                            const Eigen::MatrixXd& within, double tolerance);

// The basis of span(S) in reduced row-echelon form (k_z x s): each direction has a pivot
// coordinate with entry 1 and zeros at the others' pivots, so that a single cyclic coordinate
// reads as itself; entries below 1e-8 (the differences' noise) are set to 0.
Eigen::MatrixXd reduced_echelon(const Eigen::MatrixXd& S, std::vector<int>& pivots);

// The null space of X (orthonormal columns), singular values above tolerance non-zero.
Eigen::MatrixXd null_space(const Eigen::MatrixXd& X, double tolerance);

// An orthonormal basis of span(X) (X's columns independent).
Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& X);

}  // namespace mbd
