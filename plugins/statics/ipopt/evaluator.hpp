// Shared machinery of the statics and inverse-dynamics plugins: evaluation of a
// System at a configuration q(x) = q0 (+) x, joint coordinates, block sparsity
// patterns, and coloured finite differences of J^T lambda (the constraint
// curvature term) over a distance-2 colouring of the block graph.
//
// A block is a group of velocity columns: each rigid body's (b * vpb, vpb), then, when the
// system has flexible bodies (sdk body.hpp), one block holding all their coordinates
// (System::flexible_coordinates(), after the rigid ones), coupled with every other block.
#pragma once

#include <mbd/kit/statics.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace mbd::ipopt_plugin {

// Right Jacobian of SO(3) for the body-frame exponential map: if q = q0 (+) phi,
// a change d phi rotates the body by d pi_bar = Jr(phi) d phi (body axes).
inline Mat3 right_jacobian(const Vec3& phi) {
    const double a = phi.norm();
    const Mat3 K = skew(phi);
    if (a < 1e-6) return Mat3::Identity() - 0.5 * K + K * K / 6.0;
    return Mat3::Identity() - (1 - std::cos(a)) / (a * a) * K + (a - std::sin(a)) / (a * a * a) * K * K;
}

// Poses of all bodies (and a ground) at q, v = 0, for calling joints and forces directly.
class Poses {
public:
    Poses(Dimension dim, int bodies) : dim_(dim) {
        if (dim == Dimension::Planar) planar_.resize(bodies); else spatial_.resize(bodies);
        pground_.ground = true;
        sground_.ground = true;
    }
    void update(const Eigen::VectorXd& q) {
        if (dim_ == Dimension::Planar) {
            for (size_t k = 0; k < planar_.size(); ++k)
                planar_[k].set(q.segment<2>(3 * k), q[3 * k + 2], Vec2::Zero(), 0.0);
        } else {
            for (size_t k = 0; k < spatial_.size(); ++k)
                spatial_[k].set(q.segment<3>(7 * k), q.segment<4>(7 * k + 3), Vec3::Zero(), Vec3::Zero());
        }
    }
    void update(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
        if (dim_ == Dimension::Planar) {
            for (size_t k = 0; k < planar_.size(); ++k)
                planar_[k].set(q.segment<2>(3 * k), q[3 * k + 2], v.segment<2>(3 * k), v[3 * k + 2]);
        } else {
            for (size_t k = 0; k < spatial_.size(); ++k)
                spatial_[k].set(q.segment<3>(7 * k), q.segment<4>(7 * k + 3), v.segment<3>(6 * k), v.segment<3>(6 * k + 3));
        }
    }
    void fill(const std::vector<int>& bodies, double t, BodyStates& out) const {
        out.t = t;
        out.planar_bodies.clear();
        out.spatial_bodies.clear();
        for (int b : bodies) {
            if (dim_ == Dimension::Planar)
                out.planar_bodies.push_back(b < 0 ? &pground_ : &planar_[b]);
            else
                out.spatial_bodies.push_back(b < 0 ? &sground_ : &spatial_[b]);
        }
    }

private:
    Dimension dim_;
    std::vector<PlanarBody> planar_;
    std::vector<SpatialBody> spatial_;
    PlanarBody pground_;
    SpatialBody sground_;
};

// A joint coordinate s(q) and its gradient (global velocity columns).
struct Coordinate {
    double value = 0.0;
    std::vector<std::pair<int, double>> grad;
    double gamma = 0.0;
};

class Evaluator {
public:
    Evaluator(System& system, double t, const std::vector<int>& coordinate_joints)
        : sys(system), dim(system.dimension()), nb(system.body_count()), vpb(velocities_per_body(system.dimension())),
          nv(system.nv()), mc(system.constraint_rows(true)), nf(system.flexible_coordinates()), nblocks(nb + (nf > 0)),
          t_(t), poses_(system.dimension(), system.body_count()), coordinate_joints_(coordinate_joints) {
        // blocks of every constraint row (joints, then drivers), then of every coordinate row
        for (int j = 0; j < sys.joint_count(); ++j) {
            const JointInfo& info = sys.joint(j);
            for (int r = 0; r < info.rows; ++r) row_bodies.push_back(real_bodies(info.bodies));
        }
        for (int d = 0; d < sys.driver_count(); ++d) row_bodies.push_back(real_bodies(sys.joint(sys.driver(d).joint).bodies));
        if (static_cast<int>(row_bodies.size()) != mc) throw std::logic_error("constraint row count mismatch");
        for (int j : coordinate_joints_) coordinate_bodies.push_back(real_bodies(sys.joint(j).bodies));
        if (nf > 0) add_flexible_rows();

        // block graph: bodies sharing a joint or a force (gravity couples nothing); the
        // flexible block with every block
        std::vector<std::set<int>> adj(nblocks);
        for (int b = 0; b < nblocks; ++b) adj[b].insert(b);
        if (nf > 0)
            for (int b = 0; b < nb; ++b) {
                adj[b].insert(nb);
                adj[nb].insert(b);
            }
        auto connect = [&](const std::vector<int>& bodies) {
            for (int a : bodies)
                for (int b : bodies)
                    if (a >= 0 && b >= 0) adj[a].insert(b);
        };
        for (int j = 0; j < sys.joint_count(); ++j) connect(sys.joint(j).bodies);
        for (int f = 0; f < sys.force_count(); ++f)
            if (sys.force(f).type != "gravity") connect(sys.force(f).bodies);
        adjacency.resize(nblocks);
        for (int b = 0; b < nblocks; ++b) adjacency[b].assign(adj[b].begin(), adj[b].end());
        // distance-2 greedy colouring
        color.assign(nblocks, -1);
        colors = 0;
        for (int a = 0; a < nblocks; ++a) {
            std::set<int> used;
            for (int b : adjacency[a])
                for (int c : adjacency[b])
                    if (color[c] >= 0) used.insert(color[c]);
            int c = 0;
            while (used.count(c)) ++c;
            color[a] = c;
            colors = std::max(colors, c + 1);
        }
        blocks.resize(nblocks);
        for (int a = 0; a < nblocks; ++a) {
            blocks[a].clear();
            for (int b : adjacency[a]) blocks[a].push_back(Eigen::MatrixXd::Zero(size(a), size(b)));
        }
        T.assign(nb, Mat3::Identity());
    }

    System& sys;
    const Dimension dim;
    const int nb, vpb, nv, mc;
    const int nf, nblocks;  // flexible coordinates; blocks (the rigid bodies, then one flexible block if nf > 0)
    std::vector<std::vector<int>> row_bodies;        // per constraint row: its blocks
    std::vector<std::vector<int>> coordinate_bodies; // per coordinate joint
    std::vector<std::vector<int>> adjacency;         // per block, sorted, including itself
    std::vector<int> color;
    int colors = 0;
    std::vector<std::vector<Eigen::MatrixXd>> blocks;  // blocks[a][k]: rows of block a, columns of adjacency[a][k]
    std::vector<Mat3> T;                              // right Jacobians (spatial), identity planar

    double time() const { return t_; }
    // block a's first velocity column and its column count
    int offset(int a) const { return a < nb ? a * vpb : nb * vpb; }
    int size(int a) const { return a < nb ? vpb : nf; }
    int block_of(int column) const { return column < nb * vpb ? column / vpb : nb; }
    // the columns of a list of blocks, laid end to end
    int width(const std::vector<int>& list) const {
        int w = 0;
        for (int a : list) w += size(a);
        return w;
    }
    int block_index(int a, int b) const {
        const auto& n = adjacency[a];
        auto it = std::lower_bound(n.begin(), n.end(), b);
        return (it != n.end() && *it == b) ? static_cast<int>(it - n.begin()) : -1;
    }

    // q = q0 (+) x and the right Jacobians of the rotation increments.
    void configure(const Eigen::VectorXd& q0, const Eigen::VectorXd& x, Eigen::VectorXd& q) {
        q = q0;
        sys.advance_positions(q, x);
        if (dim == Dimension::Spatial)
            for (int b = 0; b < nb; ++b) T[b] = right_jacobian(x.segment<3>(6 * b + 3));
    }
    // row-vector (1 x size(body)) times T_b, in place (a rotation increment's right Jacobian)
    void times_T(int body, double* row) const {
        if (dim == Dimension::Planar || body >= nb) return;
        Eigen::Map<Eigen::Matrix<double, 1, 3>> w(row + 3);
        const Eigen::Matrix<double, 1, 3> r = w * T[body];
        w = r;
    }

    State state(const Eigen::VectorXd& q) const {
        State s;
        s.t = t_;
        s.q = q;
        s.v = Eigen::VectorXd::Zero(nv);
        return s;
    }

    Coordinate coordinate(int joint, const Eigen::VectorXd& q, const Eigen::VectorXd* v = nullptr) {
        if (v) poses_.update(q, *v); else poses_.update(q);
        const JointInfo& info = sys.joint(joint);
        poses_.fill(info.bodies, t_, view_);
        CoordinateEval ce;
        ce.J.setZero(vpb * static_cast<int>(info.bodies.size()));
        info.joint->coordinate(view_, ce);
        Coordinate out;
        out.value = ce.value;
        out.gamma = ce.gamma;
        for (size_t k = 0; k < info.bodies.size(); ++k) {
            const int b = info.bodies[k];
            if (b < 0) continue;
            for (int c = 0; c < vpb; ++c) out.grad.emplace_back(b * vpb + c, ce.J[vpb * k + c]);
        }
        return out;
    }

    // Sum of J^T lambda (all constraint rows) and J_s^T nu (coordinate joints) at q.
    Eigen::VectorXd jt_product(const Eigen::VectorXd& q, const Eigen::VectorXd& lambda, const Eigen::VectorXd& nu) {
        Eigen::VectorXd g = Eigen::VectorXd::Zero(nv);
        if (mc > 0) {
            sys.constraints(state(q), cv_, true);
            g += cv_.J.transpose() * lambda;
        }
        for (size_t k = 0; k < coordinate_joints_.size(); ++k) {
            if (nu.size() == 0 || nu[k] == 0.0) continue;
            const Coordinate c = coordinate(coordinate_joints_[k], q);
            for (const auto& e : c.grad) g[e.first] += e.second * nu[k];
        }
        return g;
    }

    void clear_blocks() {
        for (auto& row : blocks)
            for (auto& b : row) b.setZero();
    }

    // blocks += scale * dQ/dq at q (v = 0): exact Jacobians from the force elements;
    // gravity is skipped (constant generalized force on centroidal bodies).
    void add_force_jacobian(const Eigen::VectorXd& q, double scale) {
        if (nf > 0) return add_system_force_jacobian(q, scale);
        poses_.update(q);
        for (int f = 0; f < sys.force_count(); ++f) {
            const ForceInfo& info = sys.force(f);
            if (info.type == "gravity") continue;
            const int n = vpb * static_cast<int>(info.bodies.size());
            Eigen::MatrixXd dq = Eigen::MatrixXd::Zero(n, n), dv = Eigen::MatrixXd::Zero(n, n);
            if (info.force->has_jacobians()) {
                poses_.fill(info.bodies, t_, view_);
                info.force->jacobians(view_, dq, dv);
            } else {
                // central differences over the element's bodies
                const double h = 1e-7;
                for (size_t b = 0; b < info.bodies.size(); ++b) {
                    if (info.bodies[b] < 0) continue;
                    for (int c = 0; c < vpb; ++c) {
                        Eigen::VectorXd Qs[2];
                        for (int s = 0; s < 2; ++s) {
                            Eigen::VectorXd dx = Eigen::VectorXd::Zero(nv);
                            dx[info.bodies[b] * vpb + c] = s == 0 ? h : -h;
                            Eigen::VectorXd qp = q;
                            sys.advance_positions(qp, dx);
                            poses_.update(qp);
                            poses_.fill(info.bodies, t_, view_);
                            Qs[s] = Eigen::VectorXd::Zero(n);
                            info.force->evaluate(view_, Qs[s]);
                        }
                        dq.col(vpb * b + c) = (Qs[0] - Qs[1]) / (2 * h);
                    }
                }
                poses_.update(q);
            }
            for (size_t a = 0; a < info.bodies.size(); ++a) {
                const int ba = info.bodies[a];
                if (ba < 0) continue;
                for (size_t b = 0; b < info.bodies.size(); ++b) {
                    const int bb = info.bodies[b];
                    if (bb < 0) continue;
                    blocks[ba][block_index(ba, bb)] += scale * dq.block(vpb * a, vpb * b, vpb, vpb);
                }
            }
        }
    }

    // blocks += scale * dQ/dq at q from the System's own Jacobians, which map the forces on
    // flexible bodies and hold their elastic stiffness (sdk body.hpp).
    void add_system_force_jacobian(const Eigen::VectorXd& q, double scale) {
        Eigen::SparseMatrix<double> dq, dv;
        sys.force_jacobians(state(q), dq, dv);
        for (int col = 0; col < dq.outerSize(); ++col)
            for (Eigen::SparseMatrix<double>::InnerIterator it(dq, col); it; ++it) {
                const int a = block_of(static_cast<int>(it.row())), b = block_of(col);
                const int k = block_index(a, b);
                if (k < 0) throw std::logic_error("a force couples blocks the statics graph does not");
                blocks[a][k](it.row() - offset(a), col - offset(b)) += scale * it.value();
            }
    }

    // blocks += scale * d(J^T lambda + J_s^T nu)/dq at q, by coloured central differences.
    void add_constraint_curvature(const Eigen::VectorXd& q, const Eigen::VectorXd& lambda, const Eigen::VectorXd& nu,
                                  double scale) {
        if (lambda.size() && lambda.cwiseAbs().maxCoeff() == 0.0 && (nu.size() == 0 || nu.cwiseAbs().maxCoeff() == 0.0))
            return;
        const double h = 1e-6;
        for (int c = 0; c < colors; ++c) {
            int widest = 0;  // column d of every block of colour c at once
            for (int b = 0; b < nblocks; ++b)
                if (color[b] == c) widest = std::max(widest, size(b));
            for (int d = 0; d < widest; ++d) {
                Eigen::VectorXd dx = Eigen::VectorXd::Zero(nv);
                for (int b = 0; b < nblocks; ++b)
                    if (color[b] == c && d < size(b)) dx[offset(b) + d] = h;
                Eigen::VectorXd qp = q, qm = q;
                sys.advance_positions(qp, dx);
                sys.advance_positions(qm, -dx);
                const Eigen::VectorXd diff = (jt_product(qp, lambda, nu) - jt_product(qm, lambda, nu)) / (2 * h);
                for (int r = 0; r < nblocks; ++r)
                    for (size_t k = 0; k < adjacency[r].size(); ++k) {
                        const int b = adjacency[r][k];
                        if (color[b] == c && d < size(b)) blocks[r][k].col(d) += scale * diff.segment(offset(r), size(r));
                    }
            }
        }
    }

    // Dense matrix of the blocks (v coordinates).
    Eigen::MatrixXd dense_blocks() const {
        Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nv, nv);
        for (int a = 0; a < nblocks; ++a)
            for (size_t k = 0; k < adjacency[a].size(); ++k) {
                const int b = adjacency[a][k];
                K.block(offset(a), offset(b), size(a), size(b)) = blocks[a][k];
            }
        return K;
    }
    Eigen::SparseMatrix<double> sparse_blocks() const {
        std::vector<Eigen::Triplet<double>> t;
        for (int a = 0; a < nblocks; ++a)
            for (size_t k = 0; k < adjacency[a].size(); ++k) {
                const int b = adjacency[a][k];
                for (int i = 0; i < size(a); ++i)
                    for (int j = 0; j < size(b); ++j) t.emplace_back(offset(a) + i, offset(b) + j, blocks[a][k](i, j));
            }
        Eigen::SparseMatrix<double> K(nv, nv);
        K.setFromTriplets(t.begin(), t.end());
        return K;
    }

    ConstraintValues& constraint_values() { return cv_; }

private:
    // The flexible block joins each constraint row that reaches a flexible coordinate (a
    // joint at a flexible body: its rows' pattern holds every column of that body).
    void add_flexible_rows() {
        if (mc == 0) return;
        sys.constraints(state(sys.initial_state().q), cv_, true);
        const Eigen::SparseMatrix<double, Eigen::RowMajor> J = cv_.J;
        for (int r = 0; r < mc; ++r)
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(J, r); it; ++it)
                if (it.col() >= nb * vpb) {
                    row_bodies[r].push_back(nb);
                    break;
                }
    }

    static std::vector<int> real_bodies(const std::vector<int>& bodies) {
        std::vector<int> out;
        for (int b : bodies)
            if (b >= 0 && std::find(out.begin(), out.end(), b) == out.end()) out.push_back(b);
        return out;
    }

    double t_;
    Poses poses_;
    BodyStates view_;
    ConstraintValues cv_;
    std::vector<int> coordinate_joints_;
};

}  // namespace mbd::ipopt_plugin
