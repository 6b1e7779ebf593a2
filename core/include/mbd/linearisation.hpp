// Linearised equations of motion in independent coordinates (issue 17), about a static
// equilibrium or a steady motion: x' = A x + B u with x = (z, w), z the independent
// position increments of a coordinate partition of the holonomic constraint Jacobian J
// (book Sec. 6.5) and w the independent velocities of a partition of all the velocity rows,
// [J; A_nh] (the nonholonomic rows, e.g. no-slip contacts, constrain velocities only, so
// dim z >= dim w), u the scene's actuator efforts.
//
// The reduced equations (book Eqs. 6.79-6.99): from (z, w) the dependent positions follow
// by Newton-Raphson holding z (Sec. 6.12), the dependent velocities from [J; A_nh] v + C_t = 0
// (Eq. 6.169), and the accelerations from the augmented system
// [M J^T; J 0] [vdot; lambda] = [Q; gamma] over every row (Eq. 6.128).
//
// A steady motion (reference_motion.hpp): each body translates uniformly and turns about a
// body-fixed axis at a constant rate, v(t) = v0, and the dynamics are the same all along it
// (a wheel spinning about its axis of symmetry, a bicycle running straight). Its linearisation
// is time-invariant in coordinates that move with it: a position increment is taken about the
// reference pose of the same instant (spatial rotations about the body's reference axes, book
// Eq. 7.128's virtual rotation), and a spatial angular velocity is w_ref = A0^T A wbar, the
// body's angular velocity in its reference axes (for a body that does not turn in the
// reference, the same as the body-axis wbar to first order). Then, to first order,
//     z' = (v - v0)_i          (the body-axis velocity less the reference's; Eq. 7.128)
//     w' = (T vdot)_i,         T = diag(I, A0^T A) per body (d/dt A0^T A wbar = A0^T A wbar')
// and everything is evaluated at the reference instant. A's columns are sixth-order central
// differences of these reduced equations (the z' columns of w are the exact velocity map); B
// is exact (the accelerations are linear in the efforts).
#pragma once

#include <mbd/model_system.hpp>
#include <mbd/kit/inverse.hpp>

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

namespace mbd {

// The reference state is neither an equilibrium nor a steady motion, or cannot be
// linearised: the message names the residual and what to do.
class LinearisationError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct LinearisationOptions {
    double step = 3e-3;                 // relative position difference step (times max(1, |x|)); sixth order
    // relative velocity step: large, because accelerations are quadratic in the velocities for
    // most forces (inertia, constraints), on which the central difference is then exact
    double velocity_step = 0.1;
    double residual_tolerance = 1e-8;   // accepted max |w'| at the reference (and |vdot| along a motion)
    // cyclic directions (cyclic_directions.hpp): singular values of A's response to a position
    // direction below this times max |A| count as zero (the differences' round-off is ~1e-13 of it)
    double cyclic_tolerance = 1e-9;
    // and each is confirmed by a shift of this size (m or rad) on the nonlinear equations,
    // which must leave every rate outside the set unchanged to cyclic_tolerance times
    // max(1, max |A| shift)
    double cyclic_shift = 0.05;
};

struct LinearModel {
    State reference;                        // assembled, consistent velocities
    std::vector<std::string> coordinates;   // the independent positions z, "body.angle" (k_z)
    std::vector<int> columns;               // their velocity columns
    std::vector<std::string> velocity_coordinates;  // the independent velocities w (k_w <= k_z)
    std::vector<int> velocity_columns;      // their velocity columns
    Eigen::MatrixXd A;                      // (k_z + k_w) square, state (z, w)
    Eigen::MatrixXd B;                      // (k_z + k_w) x actuators
    std::vector<std::string> inputs;        // actuator names
    Eigen::MatrixXd velocity_map;           // nv x k_w: the full v of each independent velocity (Eq. 6.80)
    Eigen::MatrixXd position_map;           // nv x k_z: the full position increment of each z (holonomic J)
    std::vector<std::string> joint_coordinates;  // joints that have a coordinate
    Eigen::MatrixXd joint_map;              // joints x k_z: their coordinate's increment per independent position
    double residual = 0.0;                  // max |w'| at the reference
    // The cyclic position directions (k_z x s, reduced row-echelon form, each with a pivot
    // coordinate of entry 1): the equations of motion do not depend on them, neither the
    // linearised (A's response to them stays among them) nor the nonlinear (a finite shift
    // along each leaves every other rate unchanged); a position on the ground, a heading, a
    // wheel's spin angle. Never found from the eigenvalues (modes.hpp).
    // A position shift carries the velocities along (each spatial body's angular velocity kept
    // in its own axes, so a wheel turned in heading spins about its new axle): the independent
    // velocities change by carried_velocities (k_w x k_z) times the shift. The state of a
    // cyclic direction d is (d, carried_velocities d).
    Eigen::MatrixXd cyclic;
    std::vector<int> cyclic_pivots;         // each one's pivot: the independent coordinate it is named by
    Eigen::MatrixXd carried_velocities;
};

// Refuses (LinearisationError naming the element and its file:line) what the linearisation
// does not model: a force loaded by a joint's reaction (Force::load_joint).
void require_linearisable(const Model& model);

// Refuses (LinearisationError) a scene without freedom at `state` (the rank of the holonomic
// rows, drivers included, is that of the assembled state's): every coordinate fixed by the
// joints, or prescribed by drivers, which the message names with what to do. linearise checks
// it too; this is for before a statics.
void require_freedom(ModelSystem& system, const State& state);

// Linearises about `reference` (its positions assembled and velocities made consistent
// first). Throws LinearisationError when the scene has no freedom (every coordinate fixed by
// the joints and drivers; the message names the drivers), the residual exceeds the tolerance, the
// constraints are singular there, the model is not linearisable (above), or the reference moves but is not a steady motion
// (reference_motion.hpp).
LinearModel linearise(ModelSystem& system, const State& reference, const std::vector<ActuatorInfo>& actuators,
                      const LinearisationOptions& options = {});

}  // namespace mbd
