// The Model: an immutable description of a multibody system, built once from a
// scene and never changed by a run (the Model/State split of Pinocchio and
// MuJoCo). A run owns a State (t, q, v).
#pragma once

#include <mbd/sdk/body.hpp>
#include <mbd/sdk/force.hpp>
#include <mbd/kit/formulation_options.hpp>
#include <mbd/sdk/joint.hpp>
#include <mbd/kit/state.hpp>
#include <mbd/sdk/time_function.hpp>
#include <mbd/visual.hpp>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

constexpr int kGround = -1;  // body index of the ground in element body lists

struct Body {
    std::string name;
    double mass = 0.0;
    Mat3 inertia = Mat3::Zero();   // about the mass centre, body axes (planar: (2,2) = J)
    // initial state (t = 0)
    Vec3 position = Vec3::Zero();  // mass centre, world (planar: z = 0)
    double angle = 0.0;            // planar
    Vec4 euler_parameters = Vec4(1, 0, 0, 0);  // spatial
    Vec3 velocity = Vec3::Zero();
    Vec3 angular_velocity = Vec3::Zero();      // world axes (planar: z component = thetadot)
    std::string where;             // file:line of its definition
    std::vector<VisualShape> visuals;  // `visual:` (empty: shapes derived from the scene)
};

// A flexible body (`flexible_bodies:`, a body plugin, sdk body.hpp). Its coordinates follow
// every rigid body's in q and v (rigid bodies keep their fixed blocks b * nqb, b * nvb):
// offset = the rigid block's size plus the sizes of the flexible bodies before it.
struct FlexibleBodyInstance {
    std::string name;
    std::string type;
    std::shared_ptr<const FlexibleBody> body;
    // its first coordinate in q and its first velocity in v (v = qdot for its own coordinates);
    // the two differ in spatial scenes, whose rigid bodies have 7 coordinates and 6 velocities
    int offset = 0;
    int v_offset = 0;
    int size = 0;    // n, its coordinate count
    std::string where;
};

// A joint's body slot on a flexible body: the joint sees the material frame at xi as a rigid
// body (sdk body.hpp), and its `bodies[slot]` holds kGround, so the rigid-body paths skip the
// slot; the chain rule J_f G adds it (constraint_system.cpp). A force element's slot likewise:
// its generalized force Q_f on the frame becomes G^T Q_f on the body (flexible_forces.cpp).
struct FlexibleAttachment {
    int slot = 0;                  // index into the element's bodies
    int body = 0;                  // index into Model::flexible_bodies
    std::vector<double> xi;        // material parameters (FlexibleBody::material_parameters())
};

struct JointInstance {
    std::string name;
    std::string type;
    std::vector<int> bodies;       // body indices, kGround for the ground
    std::vector<Marker> markers;   // joint frame on each body
    std::shared_ptr<const Joint> joint;
    std::string where;
    // `limits: [lo, hi]` on the joint coordinate (1-DOF joints; statics bounds)
    bool has_limits = false;
    double limit_lo = 0.0, limit_hi = 0.0;
    std::string limits_where;
    std::vector<FlexibleAttachment> flexible;  // its slots on flexible bodies (empty: rigid only)
};

struct ForceInstance {
    std::string name;
    std::string type;
    std::vector<int> bodies;
    std::vector<Marker> markers;
    std::shared_ptr<const Force> force;
    std::string where;
    // Q depends on neither q nor v (the core's gravity element: m g at every mass centre), so
    // its Jacobians are zero and never evaluated. Such an element may span every body: the
    // square Jacobian workspace of Data is sized by the other elements (linear in N).
    bool constant_load = false;
    int load_joint = -1;  // Force::load_joint() as an index into Model::joints, -1 none
    std::vector<FlexibleAttachment> flexible;  // its slots on flexible bodies (empty: rigid only)
};

// A driver prescribes the coordinate of a 1-DOF joint: s(q) - f(t) = 0.
struct Driver {
    std::string name;
    int joint = -1;                // index into Model::joints
    std::shared_ptr<const TimeFunction> motion;
    std::string where;
};

// An actuator (inverse dynamics): a generalized force J_s^T tau along a 1-DOF
// joint's coordinate, with effort bounds and a weight in the effort norm.
struct Actuator {
    std::string name;
    int joint = -1;                // index into Model::joints
    double lo = -1e300, hi = 1e300;  // effort bounds (N or N m); +-1e300: none
    double weight = 1.0;
    std::string where;
};

class Model {
public:
    std::string name;
    std::string source;            // scene file path (or label)
    std::vector<std::string> base_files;  // the `base:` files the scene inherits from, in the order read
    Dimension dimension = Dimension::Planar;
    Vec3 gravity = Vec3::Zero();
    std::vector<Body> bodies;      // the ground is implicit (index kGround)
    std::vector<FlexibleBodyInstance> flexible_bodies;  // `flexible_bodies:`, coordinates after the rigid ones
    std::vector<JointInstance> joints;
    std::vector<ForceInstance> forces;
    std::vector<Driver> drivers;
    std::vector<Actuator> actuators;  // `actuators:` (inverse dynamics)
    // The scene's choice of formulation (empty: none chosen; the command line decides).
    std::string formulation;
    std::shared_ptr<const Param> formulation_node;  // the `formulation:` node (name or map)
    FormulationOptions formulation_options;         // its shared keys, read (formulation_setup.hpp)
    std::string formulation_where;
    // The physics of the scene as read (every `base:` merged in, each node with its file:line;
    // without the application sections, which Scene keeps): the inputs and breakpoints are
    // found in it, and a parameter study changes it and loads it again.
    std::shared_ptr<const Param> document;

    int body_count() const { return static_cast<int>(bodies.size()); }
    int nq() const { return body_count() * coordinates_per_body(dimension) + flexible_coordinates_; }
    int nv() const { return body_count() * velocities_per_body(dimension) + flexible_coordinates_; }
    // the coordinates of every flexible body (they follow the rigid bodies' in q and v)
    int flexible_coordinates() const { return flexible_coordinates_; }
    // Appends a flexible body after the rigid bodies' coordinates and the flexible ones before it
    // (every rigid body is added first: the offsets assume the rigid block is complete).
    void add_flexible_body(FlexibleBodyInstance body);
    // Index into flexible_bodies by name, -1 when none has it.
    int flexible_body_index(const std::string& name) const;
    int q_offset(int body) const { return body * coordinates_per_body(dimension); }
    int v_offset(int body) const { return body * velocities_per_body(dimension); }

    // Index of a body by name: kGround for "ground", -2 when unknown.
    int body_index(const std::string& body_name) const;
    std::string body_name(int index) const;

    // The state given in the scene at t = 0 (not necessarily assembled).
    State initial_state() const;

private:
    int flexible_coordinates_ = 0;
};

// q <- q (+) dv: add a velocity-like increment to positions. Planar: plain sum.
// Spatial: R += dR and Euler parameters rotated by the body-frame rotation
// vector (exponential map), which keeps them normalised.
void advance_positions(const Model& model, Eigen::VectorXd& q, const Eigen::VectorXd& dv);

// Time derivative of the coordinates: planar qdot = v; spatial Rdot = v_R and
// pdot = 1/2 Gbar^T wbar (book Eq. 8.48 in Euler parameters).
Eigen::VectorXd coordinate_rates(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v);

// Rescale every body's Euler parameters to unit length (spatial); no-op planar.
void normalize_euler_parameters(const Model& model, Eigen::VectorXd& q);

// Analyses built on the holonomic rows alone (kinematics, statics, inverse dynamics, the
// linearisation of `mbd modes`) refuse a model whose joints have velocity-level
// (nonholonomic) rows, which they would silently ignore: throws InputError at the first such
// joint's file:line, naming it, `analysis` and what to do instead (`instead`).
void require_holonomic(const Model& model, const std::string& analysis, const std::string& instead);

}  // namespace mbd
