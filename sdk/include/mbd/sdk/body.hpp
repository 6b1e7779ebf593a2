// The body interface for bodies that are not rigid: what every flexible-body plugin implements
// (ANCF cables and beams, plugins/bodies/ancf; docs/plugin-sdk.md "Bodies").
//
// A flexible body owns n generalized coordinates q (any number) and n velocities v. For
// absolute nodal coordinates (ANCF, book Ch. 8's "large deformation" school) v = qdot and the
// mass matrix is constant (Shabana, Computational Continuum Mechanics, Ch. 6): a formulation
// factors it once. The equations of motion of the body alone are
//     M(q) vdot = Q_e(q, v) + Q_v(q, v) + Q_applied,
// Q_e the elastic forces (-dU/dq), Q_v the quadratic-velocity forces (zero for ANCF).
//
// Joints and forces keep seeing rigid frames. A joint or force attached to a flexible body is
// attached to a material frame: the frame at body-fixed parameters xi (the ANCF cable: the arc
// length of the reference configuration), given by frame() as a rigid body pose (PlanarBody /
// SpatialBody, whose velocities are those of the frame) together with
//     Jacobian  G   (3 or 6) x n :  frame velocity = G v  (planar [Rdot, omega], spatial [Rdot, wbar]
//                                   with wbar in the frame's own axes, as for rigid bodies)
//     bias      a   (3 or 6)     :  frame acceleration = G vdot + a
// The core evaluates the joint on the frame exactly as on a rigid body (J_f, gamma_f) and maps it
// by the chain rule to the body's coordinates:  J = J_f G,  gamma = gamma_f - J_f a  (so that
// Cddot = J vdot - gamma keeps its meaning, book Eq. 3.124); a force's Q_f maps to G^T Q_f.
// So no joint or force plugin changes, and a rigid body is the case G = I, a = 0.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/sdk/plugin.hpp>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

// What the core hands a body factory.
struct BodySpec {
    std::string name;
    std::string type;
    Dimension dimension = Dimension::Planar;
    Params params;  // the body's keys (owner "body '<name>'")
};

// A material point: position, velocity and the Jacobian of the position (= of the velocity
// with respect to v), world axes; planar bodies use the first two rows.
struct MaterialPoint {
    Vec3 r = Vec3::Zero();
    Vec3 rdot = Vec3::Zero();
    Eigen::MatrixXd jacobian;  // 3 x n (planar: rows 0, 1 meaningful, row 2 zero)
};

// A material frame seen as a rigid body (see the top of this file).
struct MaterialFrame {
    PlanarBody planar;         // planar bodies
    SpatialBody spatial;       // spatial bodies
    Eigen::MatrixXd jacobian;  // G: 3 x n planar, 6 x n spatial
    Eigen::VectorXd bias;      // a = Gdot v: 3 planar, 6 spatial
};

class MBD_SDK_API FlexibleBody {
public:
    virtual ~FlexibleBody() = default;

    // --- coordinates
    virtual int coordinates() const = 0;                         // n
    virtual Eigen::VectorXd initial_coordinates() const = 0;     // the scene's configuration
    virtual std::string coordinate_name(int k) const { return "q" + std::to_string(k); }

    // --- inertia
    // Whether mass_matrix() is the same at every q (ANCF): a formulation factors it once.
    virtual bool constant_mass() const { return false; }
    virtual void mass_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& M) const = 0;  // n x n
    // Q_v (book Eq. 5.49's quadratic velocity vector); zero for absolute nodal coordinates.
    virtual void quadratic_velocity_forces(const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/,
                                           Eigen::Ref<Eigen::VectorXd> Q) const {
        Q.setZero();
    }
    // Generalized force of a uniform acceleration field g (gravity): sum over the mass of g.
    virtual void gravity_forces(const Eigen::VectorXd& q, const Vec3& g, Eigen::Ref<Eigen::VectorXd> Q) const = 0;
    // Its potential, -(integral of g . r dm); Q of gravity_forces() is minus its gradient.
    virtual double gravity_potential(const Eigen::VectorXd& q, const Vec3& g) const = 0;

    // --- elasticity
    virtual double strain_energy(const Eigen::VectorXd& q) const = 0;                      // U
    virtual void elastic_forces(const Eigen::VectorXd& q, Eigen::Ref<Eigen::VectorXd> Q) const = 0;  // -dU/dq
    // dQ_e/dq (= -K_t, the tangent stiffness with its sign); symmetric.
    virtual void elastic_jacobian(const Eigen::VectorXd& q, Eigen::Ref<Eigen::MatrixXd> dQ_dq) const = 0;

    // --- material points and frames, at body-fixed parameters xi (material_parameters() of them)
    virtual int material_parameters() const = 0;
    // Throws InputError naming the body when xi lies outside the body.
    virtual void check_material_point(const double* xi) const = 0;
    virtual void point(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialPoint& out) const = 0;
    virtual void frame(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialFrame& out) const = 0;

    // --- nodes (for joints at nodes, outputs and drawing): each node is a material point
    virtual int node_count() const { return 0; }
    virtual std::vector<double> node_parameters(int /*node*/) const { return {}; }
};

// The chain rule of the top of this file for one body's block of an element's rows: the block J_f
// (rows x 3 planar, rows x 6 spatial) of rows evaluated on the material frame becomes J = J_f G
// (rows x n) over the body's own velocities, and gamma loses J_f a.
inline void map_frame_rows(const Eigen::Ref<const Eigen::MatrixXd>& J_frame, const MaterialFrame& frame,
                           Eigen::Ref<Eigen::MatrixXd> J_body, Eigen::Ref<Eigen::VectorXd> gamma) {
    J_body.noalias() = J_frame * frame.jacobian;
    gamma.noalias() -= J_frame * frame.bias;
}

using BodyFactory = std::unique_ptr<FlexibleBody>(const BodySpec&);

}  // namespace mbd

// Registers a body type: MBD_BODY_PLUGIN(ancf_cable, make_ancf_cable)
#define MBD_BODY_PLUGIN(type, factory) MBD_REGISTER_PLUGIN(body, type, factory)
