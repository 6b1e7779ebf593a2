// The joint interface: what every joint plugin implements.
//
// A joint connects bodies (usually two) and contributes rows to the
// constraint equations C(q, t) = 0 (book Eq. 3.108). For its rows it gives
//   C       the residual,
//   J       the Jacobian with respect to the velocities of its bodies, one block
//           of velocities_per_body columns per body in the joint's body order
//           (book Eqs. 3.130, 7.159-7.185),
//   C_t     the partial time derivative (book Eq. 3.120: J v = -C_t),
//   gamma   the acceleration right side Q_d (book Eq. 3.124: J vdot = gamma),
// so that along any motion  Cddot = J vdot - gamma.
// Columns belonging to the ground are written but ignored by the assembler.
//
// A joint may also restrict the velocities without restricting the positions
// (nonholonomic, velocity-level rows: a wheel's no-slip condition, book Sec. 1.4's
// nonholonomic constraints). For those rows it gives
//   A       the velocity coefficients (same column layout as J),
//   b       the right side, so that the constraint is  A(q, t) v = b(q, t),
//   gamma   the acceleration right side: A vdot = gamma along any motion that keeps
//           A v = b, i.e. gamma = db/dt - (dA/dt) v, both derivatives total (through
//           q, whose rate is v, and t),
// so that along any motion  d/dt (A v - b) = A vdot - gamma.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace mbd {

// Preallocated output of a constraint evaluation (rows x cols set by the caller).
struct ConstraintEval {
    Eigen::VectorXd C;
    Eigen::MatrixXd J;
    Eigen::VectorXd C_t;
    Eigen::VectorXd gamma;

    void resize(int rows, int cols) {
        C.setZero(rows);
        J.setZero(rows, cols);
        C_t.setZero(rows);
        gamma.setZero(rows);
    }
};

// Preallocated output of a velocity-level (nonholonomic) evaluation, rows x cols.
struct VelocityConstraintEval {
    Eigen::MatrixXd A;
    Eigen::VectorXd b;
    Eigen::VectorXd gamma;

    void resize(int rows, int cols) {
        A.setZero(rows, cols);
        b.setZero(rows);
        gamma.setZero(rows);
    }
};

// A scalar joint coordinate s(q) (the angle of a revolute joint, the travel of a
// prismatic one): value, gradient J_s (same column layout as the joint), and
// gamma_s with sddot = J_s vdot - gamma_s. Drivers prescribe s = f(t).
struct CoordinateEval {
    double value = 0.0;
    Eigen::RowVectorXd J;
    double gamma = 0.0;
    bool periodic = false;  // angle: residuals s - f(t) are wrapped to (-pi, pi]
};

// Relative-coordinate description of a joint (joint-constraint notes Sec. 5):
// the free relative motions of the joint frame on body j with respect to the
// joint frame on body i, about/along axes of the frame on body i, applied in
// order. Recursive formulations use it to treat the joint as a tree edge.
struct RelativeMotion {
    enum class Kind { Revolute, Prismatic, Helical, Ball };
    struct Freedom {
        Kind kind;
        Vec3 axis;           // unit, in the joint frame of body i
        double pitch = 0.0;  // helical: translation per radian
    };
    std::vector<Freedom> freedoms;
};
inline RelativeMotion::Freedom revolute_about(const Vec3& axis) {
    return {RelativeMotion::Kind::Revolute, axis, 0.0};
}
inline RelativeMotion::Freedom prismatic_along(const Vec3& axis) {
    return {RelativeMotion::Kind::Prismatic, axis, 0.0};
}

// What the core hands a joint factory.
struct JointSpec {
    std::string name;
    std::string type;
    Dimension dimension = Dimension::Planar;
    std::vector<BodyInfo> bodies;   // the connected bodies, in the scene's order
    std::vector<Marker> markers;    // the joint frame on each body (coincident at t = 0)
    Params params;                  // keys not consumed by the core
};

class MBD_SDK_API Joint {
public:
    virtual ~Joint() = default;

    // Number of constraint equations this joint contributes.
    virtual int rows() const = 0;

    // Evaluate C, J, C_t and gamma into `out` (already sized rows() x cols).
    virtual void evaluate(const BodyStates& bodies, ConstraintEval& out) const = 0;

    // Short names of the rows for diagnostics ("x", "y", "z-parallel", ...).
    virtual std::string row_name(int row) const { return "row " + std::to_string(row); }

    // A row whose residual is periodic (it jumps by this period far from C = 0,
    // like a wrapped angle) returns the period; 0 for ordinary rows.
    virtual double row_period(int /*row*/) const { return 0.0; }

    // 1-DOF joints expose their coordinate so a driver can prescribe it.
    virtual bool has_coordinate() const { return false; }
    virtual void coordinate(const BodyStates& /*bodies*/, CoordinateEval& /*out*/) const {}

    // Whether gamma (of evaluate(), and of coordinate() for a joint with a coordinate) may depend
    // on the translational velocities Rdot of the joint's bodies. A joint whose gamma is a
    // function of the angular velocities alone (body-fixed points and directions: a pin, a ball
    // joint; book Eqs. 3.133, 7.166, 7.170) returns false, and the Hamiltonian formulation's
    // polarization of Jdot^T mu skips the translational components (jdot_transpose.hpp). The safe
    // default is true.
    virtual bool gamma_depends_on_translation() const { return true; }

    // Optional, for speed: the velocity derivative of gamma, transposed and weighted. gamma (of
    // evaluate()) is quadratic in the velocities of the joint's bodies; a joint that says
    // has_gamma_velocity_transpose() adds (d gamma / d v)^T w to out, for weights w (rows()
    // entries) and out over its bodies' velocity components in the order of evaluate()'s columns
    // (nvb per body: planar [xdot, ydot, thetadot], spatial [Rdot, wbar]). The Hamiltonian
    // formulation needs this product (Jdot^T mu, jdot_transpose.hpp); without the hook it finds it
    // by differences of gamma at probe velocities, 2 evaluations of every joint per probe.
    // `mbd plugin check` compares the two.
    virtual bool has_gamma_velocity_transpose() const { return false; }
    virtual void gamma_velocity_transpose(const BodyStates& /*bodies*/, const double* /*weights*/,
                                          double* /*out*/) const {}

    // Joints that are tree edges describe their free relative motions.
    virtual std::optional<RelativeMotion> relative_motion() const { return std::nullopt; }

    // Velocity-level (nonholonomic) rows, A v = b: none unless a joint has them. They
    // follow every holonomic row and driver in a System's stack (system.hpp).
    virtual int velocity_rows() const { return 0; }
    // Evaluate A, b and gamma into `out` (already sized velocity_rows() x cols).
    virtual void evaluate_velocity(const BodyStates& /*bodies*/, VelocityConstraintEval& /*out*/) const {}
    virtual std::string velocity_row_name(int row) const { return "velocity row " + std::to_string(row); }

    // A contact row that can only push in reality (a cam and its spring-loaded follower): the
    // sign its multiplier has while the contact is in compression (-1 or +1); 0 for an ordinary
    // row. The row itself stays bilateral; a forward-dynamics run warns, with the time, where
    // the multiplier changes sign: the contact force passes through zero and the bodies would
    // separate there (core lift_off.hpp).
    virtual int compression_sign(int /*row*/) const { return 0; }
};

}  // namespace mbd
