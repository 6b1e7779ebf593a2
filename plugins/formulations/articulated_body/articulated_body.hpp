// The articulated-body formulation of a tree of joints (no loops) written in
// joint coordinates: the recursive path of the embedding formulation (book Sec. 4.5: the
// embedding with relative joint coordinates; joint-constraint notes Sec. 5 and digest
// joints-forces-rotations Sec. 7.6 on RelativeMotion), with an O(n) articulated-body
// algorithm.
//
// Tree edges: every joint becomes an edge parent -> child (parent nearer the ground,
// topology.hpp). Its freedoms (RelativeMotion: revolute, prismatic, helical, ball) act
// in order on the parent's joint frame, T(s) = T_1(s_1) T_2(s_2) ... T_n(s_n), each about
// or along an axis through the frame origin given in the parent joint frame; an edge
// listed child-first in the scene uses the inverse motion (the same axes in reverse
// order, which spans the same set of relative poses). A body connected to nothing fixed
// is a free root (a 6-DOF edge to the ground: its own q and v).
//
// ODE state (decision): y = [s; u]: the joint coordinates (one per revolute, prismatic
// or helical freedom, four Euler parameters per ball, a free root's own q) and the joint
// speeds (one per 1-DOF freedom, three body-axis angular velocity components per ball, a
// free root's v). The absolute q, v are reconstructed by forward kinematics in O(n); the
// joint constraints then hold exactly (no drift); project() only renormalises the Euler
// parameters.
//
// Velocities: body velocity v_b = (Rdot world, wbar body axes) (the System's layout). For
// each edge v_c = Phi v_p + H u with Phi the rigid transfer (u = 0) and H the joint's
// partial velocities; vdot_c = Phi vdot_p + H udot + a with a the velocity-product term
// (the child's acceleration at vdot_p = 0, udot = 0), computed by an elementwise world
// recursion through the freedoms.
//
// Dynamics: articulated-body algorithm in these coordinates (Featherstone 1983; the
// virtual-power form of Jain's spatial operators). Body equations M_b vdot_b = Q_b + f_b
// - sum_children Phi_c^T f_c with f the joint constraint force (H^T f = 0). Leaves to
// root: P_b = M_b + sum Phi_c^T Pa_c Phi_c, z_b = -Q_b + sum Phi_c^T za_c with
// D = H^T P H, Pa = P - P H D^-1 H^T P, za = Pa a + z - P H D^-1 H^T z; root to leaves:
// udot = -D^-1 H^T (P (Phi vdot_p + a) + z), vdot = Phi vdot_p + H udot + a. Planar
// scenes run the same algorithm embedded in 3-D (z and out-of-plane rotations are never
// excited; their dummy inertias do not enter). Cost O(n) per evaluation.
//
// Driven joints (prescribed motion): a driver on a tree joint of one freedom prescribes that
// freedom, s = sign f(t) + offset (sign and offset relate the driver's coordinate s(q) to the
// edge's, read once at the assembled initial state). Its coordinate and speed leave y (the ODE
// holds the free ones only); the sweeps take its udot = sign f''(t) as known: the child's
// articulated inertia passes to the parent whole, Pa = P, za = P (a + H udot) + z, with no D to
// invert. The driver's multiplier comes with the joint's own (tree_joint_multipliers): the
// joint's rows and the driver's row together carry the force across the joint.
//
// Reactions: f_c = P_c vdot_c + z_c is the joint's constraint force on the child and
// -Phi^T f_c on the parent; each joint's multipliers follow from its own rows,
// J_k^T lambda_k = -(f on its bodies) (book Eq. 6.146, Q_c = -J^T lambda), least squares
// on the joint's few rows.
#pragma once

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/topology.hpp>

#include <Eigen/Dense>

#include <vector>

namespace mbd::articulated {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat6X = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;
using MatXX6 = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using VecX6 = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

// The rotation by `angle` about z (a planar angle as a 3 x 3 rotation).
inline Mat3 rotation_z(double angle) {
    Mat3 a = Mat3::Identity();
    a.topLeftCorner<2, 2>() = planar_rotation(angle);
    return a;
}

class ArticulatedBody : public Formulation {
public:
    MBD_FORMULATION_CALLS;
    MBD_FORMULATION_STATE_CONVERSIONS;
    int ode_size() const override { return static_cast<int>(free_s_.size() + free_u_.size()); }
    bool may_redefine_state() const override { return false; }  // joint coordinates: nothing to re-select

protected:
    struct Freedom {
        RelativeMotion::Kind kind;
        Vec3 axis;
        double pitch = 0.0;  // helical: translation per radian
        int s = 0, u = 0;    // offsets of its coordinates and speeds in y
    };
    struct Edge {
        int joint = -1;        // -1: a free root
        int body = -1, parent = -1;  // child body; parent body (-1 ground)
        int child_slot = 1, parent_slot = 0;  // the bodies' positions in the joint's body list
        Vec3 u_p = Vec3::Zero(), u_c = Vec3::Zero();   // marker origins (body coordinates)
        Mat3 A_p = Mat3::Identity(), A_c = Mat3::Identity();  // marker axes (body coordinates)
        double angle_p = 0.0, angle_c = 0.0;           // planar marker angles
        Vec4 p_p = Vec4(1, 0, 0, 0), p_c = Vec4(1, 0, 0, 0);  // Euler parameters of A_p, A_c
        std::vector<Freedom> freedoms;
        int s0 = 0, ns = 0, u0 = 0, nu = 0;
        int h0 = 0, d0 = 0;   // offsets of H (6 x nu) and D^-1 (nu x nu) in their pools
        int prescribed = -1;  // index into prescribed_ when a driver prescribes its one freedom
    };
    // a driven tree joint's freedom: s = sign f(t) + offset
    struct Prescribed {
        int driver = -1, edge = -1;
        int s = 0, u = 0;           // the freedom's indices in s_, u_
        double sign = 1.0, offset = 0.0;
        double acceleration = 0.0;  // its udot at the time of the last prescribe()
    };
    // per body, the kinematic and articulated quantities
    struct Body {
        Vec3 R = Vec3::Zero();
        Mat3 A = Mat3::Identity();
        double theta = 0.0;   // planar angle, accumulated (not wrapped)
        Vec4 p = Vec4(1, 0, 0, 0);  // spatial: Euler parameters composed along the chain (continuous)
        Vec6 v = Vec6::Zero();  // (Rdot, wbar)
        Vec3 w = Vec3::Zero();  // world angular velocity
        // Phi = [[I, S], [0, E]] (rigid transfer from the parent: S = -[R_c - R_p]x A_p, E = A_c^T A_p)
        Mat3 S = Mat3::Zero(), E = Mat3::Zero();
        Vec6 a = Vec6::Zero();
        double m = 0.0;         // mass and inertia (Jbar; planar: J on the diagonal)
        Mat3 J = Mat3::Zero();
        Mat6 P = Mat6::Zero();
        Vec6 z = Vec6::Zero();
        Vec6 vdot = Vec6::Zero();
        Vec6 f = Vec6::Zero();  // constraint force of its parent joint on it
    };

    // a joint's frame as the forward kinematics walk from the parent's marker through the
    // joint's freedoms (articulated_kinematics.cpp)
    struct JointFrame {
        Vec3 Rp = Vec3::Zero();  // the parent body's position and axes (ground: zero, identity)
        Mat3 Ap = Mat3::Identity();
        Vec3 o, odot, oddot;  // origin, its velocity, its velocity-product acceleration
        Mat3 A;               // axes
        Vec4 p;               // the axes' Euler parameters, composed along the chain (spatial)
        double theta = 0.0;   // planar angle, accumulated
        Vec3 w, alpha;        // angular velocity, its velocity-product acceleration
    };
    struct HColumn {
        Vec3 g, o, t;  // H column: [g x (R_c - o) + t; A_c^T g]
    };

    // the edges, pools and per-body inertias of the tree in `topology` (bind() after its check)
    void build(System& system, const Topology& topology);
    // build()'s parts: the edge of body b (its joint's markers and freedoms), each body's
    // mass and inertia, and the sized work vectors
    Edge tree_edge(System& system, const Topology& topology, int b) const;
    void read_inertias(System& system);
    void size_work_vectors();
    // the drivers' joints as prescribed edges (after build; a driver's joint is a tree edge of one
    // freedom, topology.hpp) and y's layout without their coordinates and speeds
    void prescribe_driven_joints(System& system);
    // s_, u_ from y at t: the free entries from y, the prescribed ones from their drivers
    void expand(double t, const Eigen::VectorXd& y);
    // y from s_, u_ (the free entries)
    void compress(Eigen::VectorXd& y) const;
    // the prescribed freedoms at t: their accelerations, and (coordinates) their s_, u_ entries
    void prescribe(double t, bool coordinates);
    // s_, u_ of a state (the joint coordinates and speeds of every edge); leaves bodies_ at (s_, 0)
    void joint_coordinates(const State& state);
    // forward kinematics: s, u -> bodies_ (poses, velocities, Phi, H, a), edge by edge: a free
    // root from its own coordinates, a child through its parent's marker frame and its freedoms
    void kinematics(const Eigen::VectorXd& s, const Eigen::VectorXd& u);
    void root_kinematics(const Edge& e, const Eigen::VectorXd& s, const Eigen::VectorXd& u);
    JointFrame parent_marker_frame(const Edge& e) const;
    int walk_freedoms(const Edge& e, const Eigen::VectorXd& s, const Eigen::VectorXd& u, JointFrame& frame,
                      HColumn* cols) const;  // returns the number of H columns written
    void place_child(const Edge& e, const JointFrame& frame, const HColumn* cols, int ncol);
    // joint_coordinates()'s parts: a body's pose in a state (-1: ground), one edge's
    // coordinates into s_, its prismatic ones, and the speeds u_ of every edge
    void body_pose(const State& state, int b, Vec3& R, Mat3& A, double& theta) const;
    void edge_coordinates(const State& state, const Edge& e);
    void prismatic_coordinates(const Edge& e, const Vec3& drel);
    void joint_speeds(const State& state);
    // bodies_ -> state (q, v)
    void write_state(double t, State& state);
    // articulated-body algorithm at bodies_ with Q (System layout): vdot, f, udot
    void articulated(double t, const Eigen::VectorXd& Q, Eigen::VectorXd& udot);
    void vdot_system(Eigen::VectorXd& vdot);
    // sdot from y = [s; u] into ydot's head (Euler parameters: book Eq. 8.48)
    void coordinate_rates(const Eigen::VectorXd& y, Eigen::VectorXd& ydot) const;
    // ydot at y from s_, u_ (expand()ed from y) and udot_: the free coordinates' rates and speeds' accelerations
    void write_ydot(const Eigen::VectorXd& y, Eigen::VectorXd& ydot);
    // each tree joint's multipliers from the force f of its child's body (bodies_[].f) and its
    // rows of cv.J: J_k^T lambda_k = -(f on its bodies), least squares on the joint's rows
    void tree_joint_multipliers(const ConstraintValues& cv, Eigen::VectorXd& lambda) const;
    Vec6 to6(const Eigen::VectorXd& x, int body) const;
    static Vec6 phi_mul(const Body& c, const Vec6& x);
    static Vec6 phiT_mul(const Body& c, const Vec6& f);
    static void add_phiT_X_phi(const Body& c, const Mat6& X, Mat6& P);

    System* system_ = nullptr;
    bool planar_ = true;
    int nb_ = 0, nq_ = 0, nv_ = 0, ns_ = 0, nu_ = 0;
    std::vector<Edge> edges_;  // parent before child
    std::vector<Body> bodies_;
    std::vector<double> sign_;
    std::vector<Mat6> mass_;  // per body, the System's block of M (its top-left 3 x 3 when planar)
    // H and D^-1 of every edge, packed (a compact working set keeps the O(n) passes in cache)
    std::vector<double> hpool_, dpool_;
    // (mapped with at most 6 columns: products with them stay in fixed-size storage, off the heap)
    Eigen::Map<Mat6X> H(const Edge& e) { return {hpool_.data() + e.h0, 6, e.nu}; }
    Eigen::Map<MatXX6> Dinv(const Edge& e) { return {dpool_.data() + e.d0, e.nu, e.nu}; }  // per body: +-1 so that written Euler parameters continue the state's
    State state_;
    Eigen::VectorXd Q_, udot_, s_, u_;  // s_, u_: every edge's coordinates and speeds (y's entries and the prescribed)
    std::vector<Prescribed> prescribed_;
    std::vector<int> free_s_, free_u_;  // y = [s_(free_s_); u_(free_u_)]
    std::vector<int> y_of_s_;           // per entry of s_: its index in y, -1 prescribed
    Eigen::VectorXd full_y_, full_ydot_;  // [s_; u_] and its rate, when joints are prescribed
};

}  // namespace mbd::articulated
