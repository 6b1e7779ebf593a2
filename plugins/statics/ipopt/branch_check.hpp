// Trust region and branch check of the statics continuation.
//
// Ipopt's iterates may leave the constraint manifold C(q) = 0 (its filter accepts
// infeasible steps) and take large steps in the angles. Unbounded, that lets it
// wander several turns (a correct equilibrium modulo 2 pi, reported at 48 rad) or
// converge on another assembly branch of a closed loop, which the mechanism cannot
// reach without coming apart. So each Ipopt solve is confined to a box around its
// centre (rotation increments within +-f pi/2, translations within +-f L, L the size
// of the model), the centre moves to the solution while that lies on the box, and
// every accepted step is verified to stay on the start's component of C = 0.
#pragma once

#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>

namespace mbd::ipopt_plugin {

// Geometry of the increments: which velocity components are rotations, and the
// length scale of the model (bounding box of the bodies and the joint points).
struct IncrementGeometry {
    Dimension dim = Dimension::Planar;
    int nb = 0, vpb = 3;
    double length = 1.0;

    // (the flexible coordinates after the rigid ones are positions and slopes, not rotations)
    bool rotation(int i) const { return i < nb * vpb && (dim == Dimension::Planar ? i % 3 == 2 : i % 6 >= 3); }
    // max over components of |x_i| / (pi/2 for rotations, L for translations)
    double scaled_size(const Eigen::VectorXd& x) const;
    // Distance between two configurations in the metric of the increments (m, rad).
    double distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;
};

IncrementGeometry increment_geometry(System& sys, const Eigen::VectorXd& q);

// Minimum-norm Newton projection onto C(q) = 0 (joints and drivers at time t):
// q <- q - J^T (J J^T)^-1 C until max |C| <= tol. A chord method: J J^T is factorised
// once and kept, across calls too (the march projects neighbouring points), until
// the contraction is slower than 1/4; the symbolic analysis is kept as well. False
// when it does not converge.
class Projector {
public:
    explicit Projector(System& sys) : sys_(sys), nv_(sys.nv()), mc_(sys.constraint_rows(true)) {}

    bool project(double t, Eigen::VectorXd& q, double tol, int max_iterations = 25);

private:
    bool factor(const Eigen::SparseMatrix<double>& J);

    System& sys_;
    int nv_, mc_;
    ConstraintValues cv_;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
    Eigen::SparseMatrix<double> J_;  // the factorised Jacobian
    bool factored_ = false, analysed_ = false;
    Eigen::Index pattern_nnz_ = -1;
};

// Is q_end = project(centre (+) x) on the same component of C = 0 as the centre (on
// C = 0)? March t = 0 .. 1 along p(t) = centre (+) t x, project every p(t) onto
// C = 0 (from p(t); from the previous projection advanced by the step when that does
// not converge) and require the projections to move continuously:
// |y(t1) - y(t0)| <= 3 |p(t1) - p(t0)| + slack, halving the step where they do not.
// A jump that survives halving down to 1e-7 of the box is a change of branch.
// Steps: at most 0.05 of the box (pi/40 rad, L/20), at least 2.
struct MarchResult {
    bool connected = true;
    int projections = 0;
    double jump_at = -1.0;  // t where the projections jump
};

MarchResult march(System& sys, Projector& projector, const IncrementGeometry& geo, double t,
                  const Eigen::VectorXd& centre, const Eigen::VectorXd& x, double tol);

}  // namespace mbd::ipopt_plugin
