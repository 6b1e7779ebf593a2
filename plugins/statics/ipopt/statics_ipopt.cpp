// Statics with Ipopt (plugin kind "statics", type "ipopt"). See docs/statics.md.
//
// Two nonlinear programs over position increments x (q = q0 (+) x):
//  potential    min V(q)  s.t. C(q) = 0, lo <= s_k(q) <= hi       (all forces conservative at rest)
//               Ipopt's multipliers are the Lagrange multipliers: -Q + J^T lambda + J_s^T nu = 0.
//               Hessian: exact (-dQ/dq from the force elements, constraint curvature
//               sum lambda_i d2C_i by coloured central differences of J^T lambda), or L-BFGS.
//  virtual-work unknowns (x, lambda, mu_lo, mu_hi): C(q) = 0, Q - J^T lambda - J_s^T (mu_hi - mu_lo) = 0,
//               lo <= s_k <= hi, mu >= 0, objective sum mu_lo (s - lo) + mu_hi (hi - s) (complementarity,
//               zero at a solution). Without limits this is a square system solved by Newton steps.
//               Hessian: limited-memory.
#include "evaluator.hpp"
#include "ipopt_common.hpp"
#include "relaxation.hpp"

#include <mbd/sdk/statics.hpp>

#include <IpIpoptApplication.hpp>
#include <IpIpoptData.hpp>
#include <IpTNLP.hpp>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>

namespace mbd::ipopt_plugin {
namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr double kInf = 1e19;

class StaticsNLP : public Ipopt::TNLP {
public:
    // x_bound: the trust region |x_i| <= x_bound[i] around q0 (empty: unbounded).
    // tail0: starting values of the unknowns after x (virtual-work: lambda, mu_lo, mu_hi).
    StaticsNLP(Evaluator& ev, const Eigen::VectorXd& q0, const std::vector<JointLimit>& limits, bool potential,
               bool exact_hessian, const Eigen::VectorXd& tail0, const Eigen::VectorXd& x_bound)
        : ev_(ev), q0_(q0), limits_(limits), potential_(potential), exact_(exact_hessian && potential),
          nv_(ev.nv), mc_(ev.mc), nl_(static_cast<int>(limits.size())), vpb_(ev.vpb), lambda0_(tail0),
          x_bound_(x_bound) {
        n_ = potential_ ? nv_ : nv_ + mc_ + 2 * nl_;
        m_ = potential_ ? mc_ + nl_ : mc_ + nv_ + nl_;
        off_s_ = potential_ ? mc_ : mc_ + nv_;
        for (const auto& rb : ev_.row_bodies) ncj_ += static_cast<int>(rb.size()) * vpb_;
        for (const auto& cb : ev_.coordinate_bodies) nsj_ += static_cast<int>(cb.size()) * vpb_;
        for (int a = 0; a < ev_.nb; ++a) {
            nblock_ += static_cast<int>(ev_.adjacency[a].size()) * vpb_ * vpb_;
            for (int b : ev_.adjacency[a]) {
                if (b < a) nh_ += vpb_ * vpb_;
                if (b == a) nh_ += vpb_ * (vpb_ + 1) / 2;
            }
        }
    }

    // results
    Ipopt::SolverReturn solver_status = Ipopt::UNASSIGNED;
    int iterations = 0;
    Eigen::VectorXd x_final, g_multipliers;
    bool finalized = false;

    bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) override {
        n = n_;
        m = m_;
        nnz_jac_g = ncj_ + nsj_ + (potential_ ? 0 : nblock_ + ncj_ + 2 * nsj_);
        nnz_h_lag = exact_ ? nh_ : 0;
        style = C_STYLE;
        return true;
    }

    bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
        for (Index i = 0; i < n; ++i) {
            x_l[i] = -kInf;
            x_u[i] = kInf;
        }
        if (x_bound_.size() == nv_)
            for (int i = 0; i < nv_; ++i) {
                x_l[i] = -x_bound_[i];
                x_u[i] = x_bound_[i];
            }
        if (!potential_)
            for (int k = 0; k < 2 * nl_; ++k) x_l[nv_ + mc_ + k] = 0.0;
        for (Index i = 0; i < m; ++i) g_l[i] = g_u[i] = 0.0;
        for (int k = 0; k < nl_; ++k) {
            g_l[off_s_ + k] = limits_[k].lo;
            g_u[off_s_ + k] = limits_[k].hi;
        }
        return true;
    }

    bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index, bool init_lambda,
                            Number*) override {
        if (init_z || init_lambda) return false;
        if (init_x) {
            for (Index i = 0; i < n; ++i) x[i] = 0.0;
            if (!potential_)
                for (int r = 0; r < n - nv_ && r < lambda0_.size(); ++r) x[nv_ + r] = lambda0_[r];
        }
        return true;
    }

    bool eval_f(Index n, const Number* x, bool new_x, Number& obj) override {
        return guard([&] {
            update(x, new_x);
            if (potential_) {
                obj = ev_.sys.potential_energy(ev_.state(q_));
            } else {
                obj = 0.0;
                for (int k = 0; k < nl_; ++k)
                    obj += x[nv_ + mc_ + k] * (s_[k].value - limits_[k].lo) + x[nv_ + mc_ + nl_ + k] * (limits_[k].hi - s_[k].value);
            }
            (void)n;
        });
    }

    bool eval_grad_f(Index n, const Number* x, bool new_x, Number* grad) override {
        return guard([&] {
            update(x, new_x);
            for (Index i = 0; i < n; ++i) grad[i] = 0.0;
            if (potential_) {
                for (int b = 0; b < ev_.nb; ++b) {
                    Eigen::Matrix<double, 6, 1> row;
                    for (int c = 0; c < vpb_; ++c) row[c] = -Q_[b * vpb_ + c];
                    ev_.times_T(b, row.data());
                    for (int c = 0; c < vpb_; ++c) grad[b * vpb_ + c] = row[c];
                }
            } else {
                for (int k = 0; k < nl_; ++k) {
                    const double w = x[nv_ + mc_ + k] - x[nv_ + mc_ + nl_ + k];
                    const std::vector<double> row = coordinate_row(k);
                    const auto& bodies = ev_.coordinate_bodies[k];
                    for (size_t p = 0; p < bodies.size(); ++p)
                        for (int c = 0; c < vpb_; ++c) grad[bodies[p] * vpb_ + c] += w * row[p * vpb_ + c];
                    grad[nv_ + mc_ + k] = s_[k].value - limits_[k].lo;
                    grad[nv_ + mc_ + nl_ + k] = limits_[k].hi - s_[k].value;
                }
            }
        });
    }

    bool eval_g(Index, const Number* x, bool new_x, Index m, Number* g) override {
        return guard([&] {
            update(x, new_x);
            for (Index i = 0; i < m; ++i) g[i] = 0.0;
            for (int r = 0; r < mc_; ++r) g[r] = cv_.C[r];
            if (!potential_) {
                const Eigen::VectorXd R = residual_vector(x);
                for (int i = 0; i < nv_; ++i) g[mc_ + i] = R[i];
            }
            for (int k = 0; k < nl_; ++k) g[off_s_ + k] = s_[k].value;
        });
    }

    bool eval_jac_g(Index, const Number* x, bool new_x, Index, Index nele, Index* iRow, Index* jCol,
                    Number* values) override {
        return guard([&] {
            Index e = 0;
            const bool fill = values != nullptr;
            if (fill) update(x, new_x);
            // C rows: J T
            for (int r = 0; r < mc_; ++r) {
                const auto& bodies = ev_.row_bodies[r];
                std::vector<double> row;
                if (fill) row = constraint_row(r);
                for (size_t p = 0; p < bodies.size(); ++p)
                    for (int c = 0; c < vpb_; ++c, ++e) {
                        if (fill) values[e] = row[p * vpb_ + c];
                        else { iRow[e] = r; jCol[e] = bodies[p] * vpb_ + c; }
                    }
            }
            if (!potential_) {
                // R rows, x columns: (dQ/dq - d(J^T lambda + J_s^T nu)/dq) T
                if (fill) {
                    ev_.clear_blocks();
                    ev_.add_force_jacobian(q_, 1.0);
                    ev_.add_constraint_curvature(q_, lambda_of(x), nu_of(x), -1.0);
                }
                for (int a = 0; a < ev_.nb; ++a)
                    for (size_t k = 0; k < ev_.adjacency[a].size(); ++k) {
                        const int b = ev_.adjacency[a][k];
                        Eigen::MatrixXd B;
                        if (fill) B = right_T(ev_.blocks[a][k], b);
                        for (int i = 0; i < vpb_; ++i)
                            for (int j = 0; j < vpb_; ++j, ++e) {
                                if (fill) values[e] = B(i, j);
                                else { iRow[e] = mc_ + a * vpb_ + i; jCol[e] = b * vpb_ + j; }
                            }
                    }
                // R rows, lambda columns: -J^T
                for (int r = 0; r < mc_; ++r) {
                    const auto& bodies = ev_.row_bodies[r];
                    std::vector<double> row;
                    if (fill) row = raw_constraint_row(r);
                    for (size_t p = 0; p < bodies.size(); ++p)
                        for (int c = 0; c < vpb_; ++c, ++e) {
                            if (fill) values[e] = -row[p * vpb_ + c];
                            else { iRow[e] = mc_ + bodies[p] * vpb_ + c; jCol[e] = nv_ + r; }
                        }
                }
                // R rows, mu columns: +J_s^T (mu_lo), -J_s^T (mu_hi)
                for (int side = 0; side < 2; ++side)
                    for (int k = 0; k < nl_; ++k) {
                        const auto& bodies = ev_.coordinate_bodies[k];
                        std::vector<double> row;
                        if (fill) row = raw_coordinate_row(k);
                        for (size_t p = 0; p < bodies.size(); ++p)
                            for (int c = 0; c < vpb_; ++c, ++e) {
                                if (fill) values[e] = (side == 0 ? 1.0 : -1.0) * row[p * vpb_ + c];
                                else { iRow[e] = mc_ + bodies[p] * vpb_ + c; jCol[e] = nv_ + mc_ + side * nl_ + k; }
                            }
                    }
            }
            // limit rows: J_s T
            for (int k = 0; k < nl_; ++k) {
                const auto& bodies = ev_.coordinate_bodies[k];
                std::vector<double> row;
                if (fill) row = coordinate_row(k);
                for (size_t p = 0; p < bodies.size(); ++p)
                    for (int c = 0; c < vpb_; ++c, ++e) {
                        if (fill) values[e] = row[p * vpb_ + c];
                        else { iRow[e] = off_s_ + k; jCol[e] = bodies[p] * vpb_ + c; }
                    }
            }
            if (e != nele) throw std::logic_error("Jacobian size mismatch");
        });
    }

    bool eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda, bool,
                Index nele, Index* iRow, Index* jCol, Number* values) override {
        if (!exact_) return false;
        return guard([&] {
            const bool fill = values != nullptr;
            if (fill) {
                update(x, new_x);
                ev_.clear_blocks();
                if (obj_factor != 0.0) ev_.add_force_jacobian(q_, -obj_factor);
                Eigen::VectorXd lam = Eigen::Map<const Eigen::VectorXd>(lambda, mc_);
                Eigen::VectorXd nu = Eigen::Map<const Eigen::VectorXd>(lambda + mc_, nl_);
                ev_.add_constraint_curvature(q_, lam, nu, 1.0);
            }
            Index e = 0;
            for (int a = 0; a < ev_.nb; ++a)
                for (size_t k = 0; k < ev_.adjacency[a].size(); ++k) {
                    const int b = ev_.adjacency[a][k];
                    if (b > a) continue;
                    Eigen::MatrixXd S;
                    if (fill) {
                        const Eigen::MatrixXd Hab = left_T(right_T(ev_.blocks[a][k], b), a);
                        const Eigen::MatrixXd Hba = left_T(right_T(ev_.blocks[b][ev_.block_index(b, a)], a), b);
                        S = 0.5 * (Hab + Hba.transpose());
                    }
                    for (int i = 0; i < vpb_; ++i)
                        for (int j = 0; j < vpb_; ++j) {
                            if (b == a && j > i) continue;
                            if (fill) values[e] = S(i, j);
                            else { iRow[e] = a * vpb_ + i; jCol[e] = b * vpb_ + j; }
                            ++e;
                        }
                }
            if (e != nele) throw std::logic_error("Hessian size mismatch");
        });
    }

    void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number*, const Number*, Index m,
                           const Number*, const Number* lambda, Number, const Ipopt::IpoptData* ip_data,
                           Ipopt::IpoptCalculatedQuantities*) override {
        solver_status = status;
        x_final = Eigen::Map<const Eigen::VectorXd>(x, n);
        g_multipliers = Eigen::Map<const Eigen::VectorXd>(lambda, m);
        if (ip_data) iterations = ip_data->iter_count();
        finalized = true;
    }

    std::string callback_error;

private:
    template <class F>
    bool guard(F&& f) {
        try {
            f();
            return true;
        } catch (const std::exception& e) {
            if (callback_error.empty()) callback_error = e.what();
            return false;
        }
    }

    void update(const Number* x, bool new_x) {
        if (!new_x && have_) return;
        const Eigen::VectorXd xv = Eigen::Map<const Eigen::VectorXd>(x, nv_);
        ev_.configure(q0_, xv, q_);
        const State st = ev_.state(q_);
        if (mc_ > 0) {
            ev_.sys.constraints(st, cv_, true);
            Jrow_ = cv_.J;
        } else {
            cv_.C.resize(0);
        }
        ev_.sys.generalized_forces(st, Q_);
        s_.clear();
        for (const auto& l : limits_) s_.push_back(ev_.coordinate(l.joint, q_));
        have_ = true;
    }

    Eigen::VectorXd lambda_of(const Number* x) const { return Eigen::Map<const Eigen::VectorXd>(x + nv_, mc_); }
    Eigen::VectorXd nu_of(const Number* x) const {
        Eigen::VectorXd nu(nl_);
        for (int k = 0; k < nl_; ++k) nu[k] = x[nv_ + mc_ + nl_ + k] - x[nv_ + mc_ + k];
        return nu;
    }
    Eigen::VectorXd residual_vector(const Number* x) const {
        Eigen::VectorXd R = Q_;
        if (mc_ > 0) R -= cv_.J.transpose() * lambda_of(x);
        const Eigen::VectorXd nu = nu_of(x);
        for (int k = 0; k < nl_; ++k)
            for (const auto& e : s_[k].grad) R[e.first] -= e.second * nu[k];
        return R;
    }

    // Constraint row r of J over its bodies' columns, raw and times T.
    std::vector<double> raw_constraint_row(int r) const {
        const auto& bodies = ev_.row_bodies[r];
        std::vector<double> row(bodies.size() * vpb_, 0.0);
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Jrow_, r); it; ++it) {
            const int b = static_cast<int>(it.col()) / vpb_;
            auto pos = std::find(bodies.begin(), bodies.end(), b);
            if (pos != bodies.end()) row[(pos - bodies.begin()) * vpb_ + it.col() % vpb_] = it.value();
        }
        return row;
    }
    std::vector<double> constraint_row(int r) const {
        std::vector<double> row = raw_constraint_row(r);
        const auto& bodies = ev_.row_bodies[r];
        for (size_t p = 0; p < bodies.size(); ++p) ev_.times_T(bodies[p], row.data() + p * vpb_);
        return row;
    }
    std::vector<double> raw_coordinate_row(int k) const {
        const auto& bodies = ev_.coordinate_bodies[k];
        std::vector<double> row(bodies.size() * vpb_, 0.0);
        for (const auto& e : s_[k].grad) {
            auto pos = std::find(bodies.begin(), bodies.end(), e.first / vpb_);
            if (pos != bodies.end()) row[(pos - bodies.begin()) * vpb_ + e.first % vpb_] += e.second;
        }
        return row;
    }
    std::vector<double> coordinate_row(int k) const {
        std::vector<double> row = raw_coordinate_row(k);
        const auto& bodies = ev_.coordinate_bodies[k];
        for (size_t p = 0; p < bodies.size(); ++p) ev_.times_T(bodies[p], row.data() + p * vpb_);
        return row;
    }
    Eigen::MatrixXd right_T(const Eigen::MatrixXd& B, int body) const {
        if (ev_.dim == Dimension::Planar) return B;
        Eigen::MatrixXd out = B;
        out.rightCols<3>() = B.rightCols<3>() * ev_.T[body];
        return out;
    }
    Eigen::MatrixXd left_T(const Eigen::MatrixXd& B, int body) const {
        if (ev_.dim == Dimension::Planar) return B;
        Eigen::MatrixXd out = B;
        out.bottomRows<3>() = ev_.T[body].transpose() * B.bottomRows<3>();
        return out;
    }

    Evaluator& ev_;
    Eigen::VectorXd q0_;
    std::vector<JointLimit> limits_;
    bool potential_, exact_;
    int nv_, mc_, nl_, vpb_;
    Eigen::VectorXd lambda0_, x_bound_;
    int n_ = 0, m_ = 0, off_s_ = 0, ncj_ = 0, nsj_ = 0, nblock_ = 0, nh_ = 0;
    // cache at the current x
    bool have_ = false;
    Eigen::VectorXd q_, Q_;
    ConstraintValues cv_;
    Eigen::SparseMatrix<double, Eigen::RowMajor> Jrow_;
    std::vector<Coordinate> s_;
};

// True when Q(q, v = 0) = -grad V at q0 and at a perturbed configuration (checked
// along a few random directions): the forces are conservative at rest (damping
// does not count), so the potential can be minimised.
bool conservative_at_rest(System& sys, const State& start) {
    const int nv = sys.nv();
    std::mt19937 rng(12345);
    std::normal_distribution<double> normal;
    auto random_vector = [&] {
        Eigen::VectorXd d(nv);
        for (int i = 0; i < nv; ++i) d[i] = normal(rng);
        return d;
    };
    Eigen::VectorXd Q;
    for (int point = 0; point < 2; ++point) {
        State s = start;
        s.v.setZero(nv);
        if (point == 1) sys.advance_positions(s.q, 1e-2 * random_vector());
        sys.generalized_forces(s, Q);
        for (int trial = 0; trial < 3; ++trial) {
            const Eigen::VectorXd d = random_vector().normalized();
            const double h = 1e-6;
            State p = s, m = s;
            sys.advance_positions(p.q, h * d);
            sys.advance_positions(m.q, -h * d);
            const double dV = (sys.potential_energy(p) - sys.potential_energy(m)) / (2 * h);
            const double work = Q.dot(d);
            if (std::abs(dV + work) > 1e-6 * (std::abs(dV) + Q.norm()) + 1e-9) return false;
        }
    }
    return true;
}

// Minimum-norm least-squares lambda from J^T lambda = Q (starting multipliers).
Eigen::VectorXd initial_multipliers(System& sys, const State& s) {
    const int mc = sys.constraint_rows(true);
    if (mc == 0) return Eigen::VectorXd();
    ConstraintValues cv;
    sys.constraints(s, cv, true);
    Eigen::VectorXd Q;
    sys.generalized_forces(s, Q);
    if (sys.nv() <= 1500) {
        const Eigen::MatrixXd Jt = Eigen::MatrixXd(cv.J).transpose();
        return Jt.completeOrthogonalDecomposition().solve(Q);
    }
    Eigen::SparseMatrix<double> A = cv.J * cv.J.transpose();
    for (int i = 0; i < mc; ++i) A.coeffRef(i, i) += 1e-12 * (1.0 + A.coeffRef(i, i));
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    return ldlt.solve(cv.J * Q);
}

// ---------------------------------------------------------------- trust region and branch check
//
// Ipopt's iterates may leave the constraint manifold C(q) = 0 (its filter accepts
// infeasible steps) and take large steps in the angles. Unbounded, that lets it
// wander several turns (a correct equilibrium modulo 2 pi, reported at 48 rad) or
// converge on another assembly branch of a closed loop, which the mechanism cannot
// reach without coming apart. So each Ipopt solve is confined to a box around its
// centre (rotation increments within +-f pi/2, translations within +-f L, L the size
// of the model), the centre moves to the solution while that lies on the box, and
// every accepted step is verified to stay on the start's component of C = 0.

// Geometry of the increments: which velocity components are rotations, and the
// length scale of the model (bounding box of the bodies and the joint points).
struct IncrementGeometry {
    Dimension dim = Dimension::Planar;
    int nb = 0, vpb = 3;
    double length = 1.0;

    bool rotation(int i) const { return dim == Dimension::Planar ? i % 3 == 2 : i % 6 >= 3; }
    // max over components of |x_i| / (pi/2 for rotations, L for translations)
    double scaled_size(const Eigen::VectorXd& x) const {
        double m = 0.0;
        for (int i = 0; i < x.size(); ++i) m = std::max(m, std::abs(x[i]) / (rotation(i) ? M_PI / 2 : length));
        return m;
    }
    // Distance between two configurations in the metric of the increments (m, rad).
    double distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
        double d2 = 0.0;
        for (int k = 0; k < nb; ++k) {
            if (dim == Dimension::Planar) {
                d2 += (a.segment<3>(3 * k) - b.segment<3>(3 * k)).squaredNorm();  // unwrapped angles
            } else {
                d2 += (a.segment<3>(7 * k) - b.segment<3>(7 * k)).squaredNorm();
                const Eigen::Quaterniond pa(a[7 * k + 3], a[7 * k + 4], a[7 * k + 5], a[7 * k + 6]);
                const Eigen::Quaterniond pb(b[7 * k + 3], b[7 * k + 4], b[7 * k + 5], b[7 * k + 6]);
                const double angle = pa.normalized().angularDistance(pb.normalized());
                d2 += angle * angle;
            }
        }
        return std::sqrt(d2);
    }
};

IncrementGeometry increment_geometry(System& sys, const Eigen::VectorXd& q) {
    IncrementGeometry g;
    g.dim = sys.dimension();
    g.nb = sys.body_count();
    g.vpb = velocities_per_body(g.dim);
    const int cpb = coordinates_per_body(g.dim), nd = g.dim == Dimension::Planar ? 2 : 3;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
    auto extend = [&](const Eigen::Vector3d& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    };
    double reach = 0.0;
    for (int b = 0; b < g.nb; ++b) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        p.head(nd) = q.segment(cpb * b, nd);
        extend(p);
    }
    for (int j = 0; j < sys.joint_count(); ++j) {
        const JointInfo& info = sys.joint(j);
        for (size_t k = 0; k < info.bodies.size() && k < info.markers.size(); ++k) {
            if (info.bodies[k] < 0) extend(info.markers[k].u_bar);  // ground markers are world points
            else reach = std::max(reach, info.markers[k].u_bar.norm());
        }
    }
    double L = lo(0) <= hi(0) ? (hi - lo).norm() : 0.0;
    L = std::max(L, 2.0 * reach);
    g.length = L > 0.0 ? L : 1.0;
    return g;
}

// Minimum-norm Newton projection onto C(q) = 0 (joints and drivers at time t):
// q <- q - J^T (J J^T)^-1 C until max |C| <= tol. A chord method: J J^T is factorised
// once and kept, across calls too (the march projects neighbouring points), until
// the contraction is slower than 1/4; the symbolic analysis is kept as well. False
// when it does not converge.
class Projector {
public:
    explicit Projector(System& sys) : sys_(sys), nv_(sys.nv()), mc_(sys.constraint_rows(true)) {}

    bool project(double t, Eigen::VectorXd& q, double tol, int max_iterations = 25) {
        if (mc_ == 0) return true;
        State s;
        s.t = t;
        s.v = Eigen::VectorXd::Zero(nv_);
        double first = -1.0, previous = -1.0;
        bool fresh = false;  // factorised in this call
        for (int it = 0;; ++it) {
            s.q = q;
            sys_.constraints(s, cv_, true);
            if (!cv_.C.allFinite()) return false;
            const double c = cv_.C.cwiseAbs().maxCoeff();
            if (c <= tol) return true;
            if (first < 0) first = c;
            if (it >= max_iterations || c > 1e3 * std::max(first, tol)) return false;
            if (!factored_ || (previous >= 0 && c > 0.25 * previous)) {
                if (fresh && c > 0.9 * previous) return false;  // a fresh J does not contract either
                J_ = cv_.J;
                if (!factor(J_)) return false;
                factored_ = fresh = true;
            }
            previous = c;
            const Eigen::VectorXd dx = -(J_.transpose() * ldlt_.solve(cv_.C));
            if (!dx.allFinite()) return false;
            sys_.advance_positions(q, dx);
        }
    }

private:
    bool factor(const Eigen::SparseMatrix<double>& J) {
        Eigen::SparseMatrix<double> A = J * J.transpose();
        double dmax = 0.0;
        for (int i = 0; i < mc_; ++i) dmax = std::max(dmax, A.coeff(i, i));
        for (int i = 0; i < mc_; ++i) A.coeffRef(i, i) += 1e-12 * (dmax + 1e-300);  // redundant rows
        A.makeCompressed();
        if (!analysed_ || A.nonZeros() != pattern_nnz_) {
            ldlt_.analyzePattern(A);
            analysed_ = true;
            pattern_nnz_ = A.nonZeros();
        }
        ldlt_.factorize(A);
        return ldlt_.info() == Eigen::Success;
    }

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
                  const Eigen::VectorXd& centre, const Eigen::VectorXd& x, double tol) {
    MarchResult out;
    if (sys.constraint_rows(true) == 0) return out;
    auto point = [&](double s) {
        Eigen::VectorXd p = centre;
        sys.advance_positions(p, s * x);
        return p;
    };
    const double size = geo.scaled_size(x);
    const double dt0 = 1.0 / std::max(2.0, std::ceil(size / 0.05));
    const double slack = 1e3 * tol + 1e-9 * geo.length;
    double s0 = 0.0, dt = dt0;
    Eigen::VectorXd p0 = centre, y0 = centre;
    while (s0 < 1.0) {
        const double s1 = std::min(1.0, s0 + dt);
        const Eigen::VectorXd p1 = point(s1);
        const double dp = geo.distance(p0, p1);
        Eigen::VectorXd y1 = p1;
        ++out.projections;
        bool ok = projector.project(t, y1, tol) && geo.distance(y0, y1) <= 3.0 * dp + slack;
        if (!ok && s1 < 1.0) {  // from the previous projection, advanced by the step
            y1 = y0;
            sys.advance_positions(y1, (s1 - s0) * x);
            ++out.projections;
            ok = projector.project(t, y1, tol) && geo.distance(y0, y1) <= 3.0 * dp + slack;
        }
        if (ok) {
            s0 = s1;
            p0 = p1;
            y0 = y1;
            dt = std::min(dt0, 2.0 * dt);
            continue;
        }
        dt *= 0.5;
        if (dt * std::max(size, 1e-300) < 1e-7) {
            out.connected = false;
            out.jump_at = s0;
            return out;
        }
    }
    return out;
}

// Ipopt stopped at a solution: succeeded, or its step became too small to change x
// (at the precision floor of the gradient, e.g. stiff springs: dual infeasibility
// 8e-10 against |Q| ~ 1e4 in the 1000-body chain). The equilibrium residual is still
// checked independently (max |C|, |Q - J^T lambda|, limits <= 1e-6 (1 + max |Q|)).
bool finished(Ipopt::ApplicationReturnStatus s) {
    return succeeded(s) || s == Ipopt::Search_Direction_Becomes_Too_Small;
}

class IpoptStatics final : public StaticsSolver {
public:
    // The default objective means "the equilibrium the mechanism settles in": when the solve
    // from the start fails or ends at an unstable equilibrium, the over-damped path from the
    // start is followed to a stable one (relaxation.hpp) and the solve repeated from there.
    // An explicit objective keeps the nearest equilibrium, stable or not. Dense, without
    // joint limits (nv <= 600, no limits).
    StaticsResult solve(System& sys, const State& start, const StaticsOptions& opt) override {
        StaticsOptions assessed = opt;
        assessed.analyse_stability = true;  // the search needs the verdict
        const bool search = opt.objective == "auto" && opt.limits.empty() && sys.nv() <= 600;
        StaticsResult first = solve_from(sys, start, search ? assessed : opt);
        if (!search || (first.converged && first.stability != "unstable")) return reported(first, opt);

        Evaluator ev(sys, opt.time, {});
        const IncrementGeometry geo = increment_geometry(sys, start.q);
        Eigen::VectorXd unit(sys.nv());
        for (int i = 0; i < sys.nv(); ++i) unit[i] = geo.rotation(i) ? 1.0 : geo.length;
        Relaxation relaxation(sys, ev, unit, opt.stability_tolerance);
        const RelaxationResult relaxed = relaxation.run(start.q);
        if (opt.print_level > 0)
            std::printf("mbd statics: the solve from the start %s; relaxation: %s after %d iteration(s), %d move(s) "
                        "off an unstable equilibrium\n",
                        first.converged ? "ended at an unstable equilibrium" : "failed",
                        relaxed.converged ? "converged" : "did not converge", relaxed.iterations,
                        relaxed.displacements);
        if (!relaxed.converged) return reported(first, opt);
        State from = start;
        from.q = relaxed.q;
        StaticsResult second = solve_from(sys, from, assessed);
        if (!second.converged || second.stability == "unstable") return reported(first, opt);
        second.iterations += first.iterations;
        wrap_angles(sys, ev, start, opt, second.state);  // reported nearest to the original start
        return reported(second, opt);
    }

private:
    static StaticsResult reported(StaticsResult res, const StaticsOptions& opt) {
        if (!opt.analyse_stability && res.converged) {
            res.stability = "not assessed";
            res.tangent_eigenvalues.resize(0);
            res.tangent_dimension = 0;
        }
        return res;
    }

    StaticsResult solve_from(System& sys, const State& start, const StaticsOptions& opt) {
        StaticsResult res;
        res.state = start;
        res.state.t = opt.time;
        res.state.v = Eigen::VectorXd::Zero(sys.nv());
        const int nv = sys.nv(), mc = sys.constraint_rows(true), nl = static_cast<int>(opt.limits.size());

        bool potential;
        if (opt.objective == "potential")
            potential = true;
        else if (opt.objective == "virtual-work")
            potential = false;
        else
            potential = sys.conservative() || conservative_at_rest(sys, res.state);
        res.objective = potential ? "potential" : "virtual-work";

        std::vector<int> limit_joints;
        for (const auto& l : opt.limits) limit_joints.push_back(l.joint);
        Evaluator ev(sys, opt.time, limit_joints);

        Eigen::VectorXd lambda0 = potential ? Eigen::VectorXd() : initial_multipliers(sys, res.state);
        Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
        app->Options()->SetIntegerValue("print_level", opt.print_level);
        app->Options()->SetStringValue("sb", "yes");
        app->Options()->SetNumericValue("tol", opt.tolerance);
        app->Options()->SetNumericValue("constr_viol_tol", opt.tolerance);
        app->Options()->SetNumericValue("dual_inf_tol", opt.tolerance);
        app->Options()->SetNumericValue("compl_inf_tol", std::max(opt.tolerance, 1e-12));
        app->Options()->SetIntegerValue("max_iter", opt.max_iterations);
        app->Options()->SetStringValue("mu_strategy", "adaptive");
        app->Options()->SetStringValue("hessian_approximation",
                                       potential && opt.hessian != "limited-memory" ? "exact" : "limited-memory");
        if (const char* check = std::getenv("MBD_IPOPT_DERIVATIVE_TEST"))  // debugging aid: first-order, second-order
            app->Options()->SetStringValue("derivative_test", check);
        Ipopt::ApplicationReturnStatus status = app->Initialize();
        if (status != Ipopt::Solve_Succeeded) {
            res.status = status_name(status);
            res.message = "Ipopt could not be initialised";
            return res;
        }

        // Trust-region continuation (see above): solve in the box around the centre;
        // verify that the step stays on the start's assembly branch (else shrink the
        // box and solve again from the same centre); re-centre on the solution while it
        // lies on the box. Debugging aid (tests): MBD_STATICS_TRUST_REGION=off: no box;
        // =F (a number > 0): the box starts F times its size.
        const char* tr_env = std::getenv("MBD_STATICS_TRUST_REGION");
        const bool trust = !(tr_env && std::string(tr_env) == "off");
        double factor_max = 1.0;
        if (trust && tr_env && std::atof(tr_env) > 0) factor_max = std::atof(tr_env);
        const IncrementGeometry geo = increment_geometry(sys, start.q);
        Projector projector(sys);
        const double ctol = std::max(1e-9, 10.0 * opt.tolerance) * std::max(1.0, geo.length);
        constexpr int kMaxSegments = 100;
        constexpr double kMinFactor = 1.0 / 256;
        Eigen::VectorXd centre = res.state.q, tail = lambda0;
        if (!potential) {
            tail = Eigen::VectorXd::Zero(mc + 2 * nl);
            tail.head(lambda0.size()) = lambda0;
        }
        double factor = factor_max;
        int segments = 0, rejected = 0, total_iterations = 0;
        std::string loop_failure;
        Ipopt::SmartPtr<StaticsNLP> nlp;
        for (;;) {
            Eigen::VectorXd bound;
            if (trust) {
                bound.resize(nv);
                for (int i = 0; i < nv; ++i) bound[i] = factor * (geo.rotation(i) ? M_PI / 2 : geo.length);
            }
            nlp = new StaticsNLP(ev, centre, opt.limits, potential, opt.hessian != "limited-memory", tail, bound);
            status = app->OptimizeTNLP(nlp);
            total_iterations += nlp->iterations;
            if (!nlp->finalized) break;
            const Eigen::VectorXd x = nlp->x_final.head(nv);
            bool at_bound = false;
            for (int i = 0; i < bound.size(); ++i)
                if (std::abs(x[i]) >= (1.0 - 1e-4) * bound[i]) at_bound = true;
            // an unsuccessful solve only moves the centre when the box stopped it
            // (e.g. virtual work: no equilibrium inside the box is "infeasible")
            const bool stopped_by_box =
                at_bound && (status == Ipopt::Infeasible_Problem_Detected || status == Ipopt::Restoration_Failed);
            if (!finished(status) && !stopped_by_box) break;
            Eigen::VectorXd q_end = centre;
            sys.advance_positions(q_end, x);
            if (!projector.project(opt.time, q_end, ctol)) {
                if (!finished(status)) break;
                loop_failure = "the configuration Ipopt returned cannot be assembled (Newton on C(q) = 0 does not converge)";
                break;
            }
            if (mc > 0) {
                const MarchResult m = march(sys, projector, geo, opt.time, centre, x, ctol);
                if (!m.connected) {
                    if (trust && factor > kMinFactor) {
                        factor *= 0.25;  // smaller steps stay on the branch
                        ++rejected;
                        continue;
                    }
                    std::ostringstream msg;
                    msg << "the solver jumped to another assembly branch: the equilibrium it found is not connected to "
                           "the assembled start along the constraint manifold C(q) = 0 (marching from the start "
                           "to it, the projections onto C = 0 break off"
                        << (trust ? ", even with the step box shrunk to 1/256" : ", no step box")
                        << "), so the linkage cannot reach it without coming apart; start the scene closer to the "
                           "expected equilibrium, on the assembly you mean, or add joint limits";
                    loop_failure = msg.str();
                    break;
                }
            }
            if (finished(status)) sys.advance_positions(centre, x);  // Ipopt's point, not re-projected
            else centre = q_end;
            if (!potential) tail = nlp->x_final.tail(nlp->x_final.size() - nv);
            ++segments;
            if (!at_bound) break;
            if (segments >= kMaxSegments) {
                loop_failure = "no equilibrium within reach: after " + std::to_string(segments) +
                               " re-centred solves the solution still lies on the step box (the " +
                               (potential ? "potential keeps decreasing" : "equilibrium keeps receding") +
                               ", e.g. an unsupported body under gravity)";
                break;
            }
            factor = std::min(factor_max, 2.0 * factor);
        }
        res.status = status_name(status);
        res.iterations = total_iterations;
        if (opt.print_level > 0)
            std::printf("mbd statics: %d accepted step(s), %d rejected (left the start's assembly branch), "
                        "final box factor %g\n", segments, rejected, factor);
        if (!nlp->finalized) {
            res.message = "Ipopt stopped without a result (" + res.status + ")" +
                          (nlp->callback_error.empty() ? std::string() : ": " + nlp->callback_error);
            return res;
        }
        if (!loop_failure.empty()) {
            res.state.q = centre;  // the last configuration reached on the start's branch
            wrap_angles(sys, ev, start, opt, res.state);
            res.message = loop_failure;
            res.stability = "not assessed";
            return res;
        }

        // the equilibrium and its multipliers
        res.state.q = centre;
        if (!finished(status)) {  // report the failing solve's own point
            res.state.q = centre;
            sys.advance_positions(res.state.q, nlp->x_final.head(nv));
        }
        Eigen::VectorXd nu = Eigen::VectorXd::Zero(nl);
        if (potential) {
            res.lambda = nlp->g_multipliers.head(mc);
            nu = nlp->g_multipliers.segment(mc, nl);
        } else {
            res.lambda = nlp->x_final.segment(nv, mc);
            for (int k = 0; k < nl; ++k) nu[k] = nlp->x_final[nv + mc + nl + k] - nlp->x_final[nv + mc + k];
        }
        if (nl > 0 && nv <= 600) polish(sys, ev, res.state, res.lambda, nu, opt.limits);
        wrap_angles(sys, ev, start, opt, res.state);
        res.limit_multipliers = nu;

        // residual of the equilibrium equations
        Eigen::VectorXd Q;
        sys.generalized_forces(res.state, Q);
        Eigen::VectorXd R = Q;
        double c_max = 0.0;
        if (mc > 0) {
            ConstraintValues cv;
            sys.constraints(res.state, cv, true);
            R -= cv.J.transpose() * res.lambda;
            c_max = cv.C.cwiseAbs().maxCoeff();
        }
        double bound_violation = 0.0;
        res.limit_active.assign(nl, false);
        std::vector<int> active;
        for (int k = 0; k < nl; ++k) {
            const Coordinate c = ev.coordinate(opt.limits[k].joint, res.state.q);
            for (const auto& e : c.grad) R[e.first] -= e.second * nu[k];
            bound_violation = std::max({bound_violation, opt.limits[k].lo - c.value, c.value - opt.limits[k].hi});
            const double scale = 1e-7 * (1.0 + std::abs(c.value));
            if (c.value - opt.limits[k].lo < scale || opt.limits[k].hi - c.value < scale) {
                res.limit_active[k] = true;
                active.push_back(k);
            }
        }
        const double r_max = R.size() ? R.cwiseAbs().maxCoeff() : 0.0;
        res.residual = std::max({c_max, r_max, bound_violation});
        const double q_scale = 1.0 + (Q.size() ? Q.cwiseAbs().maxCoeff() : 0.0);
        res.converged = finished(status) && res.residual <= 1e-6 * q_scale;
        if (!res.converged) {
            std::ostringstream m;
            // Ipopt's "infeasible" covers the force balance too (virtual work: Q - J^T lambda = 0
            // is a constraint): with the joints, drivers and limits satisfied, it is the loads
            const bool geometry_holds = c_max <= ctol && bound_violation <= 0.0;
            if (status == Ipopt::Infeasible_Problem_Detected && geometry_holds)
                m << "no equilibrium exists under the applied loads: the joints, drivers and limits hold, but no "
                     "configuration balances the forces (e.g. a constant torque or force that no joint, spring or "
                     "limit can resist); check the loads, or add a spring, a driver or a limit that holds them "
                     "(Ipopt: infeasible problem)";
            else if (status == Ipopt::Infeasible_Problem_Detected)
                m << "no configuration satisfies the joints, drivers and limits together (Ipopt: infeasible problem)";
            else if (!finished(status))
                m << "Ipopt failed (" << res.status << ") after " << res.iterations << " iterations";
            else
                m << "no equilibrium: Ipopt stopped with residual " << res.residual;
            m << "; max |C| = " << c_max << ", max |Q - J^T lambda| = " << r_max;
            if (bound_violation > 0) m << ", limit violation " << bound_violation;
            if (!nlp->callback_error.empty()) m << "; " << nlp->callback_error;
            res.message = m.str();
            res.stability = "not assessed";
            return res;
        }

        if (opt.analyse_stability)
            stability(sys, ev, res, opt, active);
        else
            res.stability = "not assessed";
        return res;
    }

    // The configuration reported nearest to the start: planar angles theta_start +
    // wrap(theta - theta_start) (wrap to (-pi, pi]), Euler parameters with the sign
    // of the start's. Kept unwrapped when that would change a constraint (a driver on
    // an unwrapped angle) or a limited joint coordinate: then the path-continuous
    // angles are the ones the equations hold for.
    static void wrap_angles(System& sys, Evaluator& ev, const State& start, const StaticsOptions& opt,
                            State& state) {
        const int nb = sys.body_count(), mc = sys.constraint_rows(true);
        Eigen::VectorXd q = state.q;
        for (int b = 0; b < nb; ++b) {
            if (sys.dimension() == Dimension::Planar) {
                const double a0 = start.q[3 * b + 2];
                q[3 * b + 2] = a0 + std::remainder(q[3 * b + 2] - a0, 2 * M_PI);
            } else if (q.segment<4>(7 * b + 3).dot(start.q.segment<4>(7 * b + 3)) < 0) {
                q.segment<4>(7 * b + 3) *= -1.0;
            }
        }
        if (q == state.q) return;
        if (mc > 0) {
            ConstraintValues a, b;
            State s = state;
            sys.constraints(s, a, true);
            s.q = q;
            sys.constraints(s, b, true);
            if ((a.C - b.C).cwiseAbs().maxCoeff() > 1e-9) return;
        }
        for (const JointLimit& l : opt.limits)
            if (std::abs(ev.coordinate(l.joint, q).value - ev.coordinate(l.joint, state.q).value) > 1e-9) return;
        state.q = q;
    }

    // Interior-point iterates stop a barrier distance (~tol / nu) inside an active
    // limit. Newton steps on the square system [C; s_a - bound; Q - J^T lambda -
    // J_a^T nu_a] = 0 (active limits as equalities) put them on it exactly.
    static void polish(System& sys, Evaluator& ev, State& state, Eigen::VectorXd& lambda, Eigen::VectorXd& nu,
                       const std::vector<JointLimit>& limits) {
        const int nv = sys.nv(), mc = sys.constraint_rows(true);
        std::vector<int> act;
        std::vector<double> bound;
        for (size_t k = 0; k < limits.size(); ++k) {
            const Coordinate c = ev.coordinate(limits[k].joint, state.q);
            const double gap = 1e-6 * (1.0 + std::abs(c.value));
            if (c.value - limits[k].lo < gap) { act.push_back(static_cast<int>(k)); bound.push_back(limits[k].lo); }
            else if (limits[k].hi - c.value < gap) { act.push_back(static_cast<int>(k)); bound.push_back(limits[k].hi); }
        }
        if (act.empty()) return;
        const int na = static_cast<int>(act.size()), n = nv + mc + na;
        for (int it = 0; it < 4; ++it) {
            ConstraintValues cv;
            if (mc > 0) sys.constraints(state, cv, true);
            Eigen::VectorXd Q;
            sys.generalized_forces(state, Q);
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
            Eigen::VectorXd F = Eigen::VectorXd::Zero(n);
            Eigen::VectorXd R = Q;
            if (mc > 0) {
                const Eigen::MatrixXd J(cv.J);
                A.block(0, 0, mc, nv) = J;
                A.block(mc + na, nv, nv, mc) = -J.transpose();
                F.head(mc) = cv.C;
                R -= J.transpose() * lambda;
            }
            for (int a = 0; a < na; ++a) {
                const Coordinate c = ev.coordinate(limits[act[a]].joint, state.q);
                F[mc + a] = c.value - bound[a];
                for (const auto& e : c.grad) {
                    A(mc + a, e.first) += e.second;
                    A(mc + na + e.first, nv + mc + a) -= e.second;
                    R[e.first] -= e.second * nu[act[a]];
                }
            }
            F.tail(nv) = R;
            if (F.cwiseAbs().maxCoeff() < 1e-14 * (1.0 + Q.cwiseAbs().maxCoeff())) break;
            ev.clear_blocks();
            ev.add_force_jacobian(state.q, 1.0);
            ev.add_constraint_curvature(state.q, lambda, nu, -1.0);
            A.block(mc + na, 0, nv, nv) = ev.dense_blocks();
            const Eigen::VectorXd d = A.fullPivLu().solve(-F);
            if (!d.allFinite()) return;
            sys.advance_positions(state.q, d.head(nv));
            if (mc > 0) lambda += d.segment(nv, mc);
            for (int a = 0; a < na; ++a) nu[act[a]] += d[nv + mc + a];
        }
    }

    // Reduced Hessian of the potential on the tangent space of the active constraints:
    // K = sym(-dQ/dq) + sym(d(J^T lambda + J_s^T nu)/dq), Z^T K Z with Z a null-space basis.
    static void stability(System& sys, Evaluator& ev, StaticsResult& res, const StaticsOptions& opt,
                          const std::vector<int>& active) {
        const int nv = sys.nv(), mc = sys.constraint_rows(true);
        ev.clear_blocks();
        ev.add_force_jacobian(res.state.q, -1.0);
        ev.add_constraint_curvature(res.state.q, res.lambda, res.limit_multipliers, 1.0);
        ConstraintValues cv;
        if (mc > 0) sys.constraints(res.state, cv, true);
        std::vector<Coordinate> rows;
        for (int k : active) rows.push_back(ev.coordinate(opt.limits[k].joint, res.state.q));
        const int ma = mc + static_cast<int>(rows.size());

        if (nv <= 600) {
            Eigen::MatrixXd K = ev.dense_blocks();
            K = 0.5 * (K + K.transpose()).eval();
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(ma, nv);
            if (mc > 0) A.topRows(mc) = Eigen::MatrixXd(cv.J);
            for (size_t k = 0; k < rows.size(); ++k)
                for (const auto& e : rows[k].grad) A(mc + k, e.first) += e.second;
            Eigen::MatrixXd Z;
            if (ma == 0) {
                Z = Eigen::MatrixXd::Identity(nv, nv);
            } else {
                Eigen::BDCSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
                const Eigen::VectorXd& s = svd.singularValues();
                int rank = 0;
                for (int i = 0; i < s.size(); ++i)
                    if (s[i] > 1e-9 * std::max(1.0, s[0])) ++rank;
                Z = svd.matrixV().rightCols(nv - rank);
            }
            res.tangent_dimension = static_cast<int>(Z.cols());
            if (Z.cols() == 0) {
                res.stability = "stable";  // fully constrained: no motion possible
                res.tangent_eigenvalues.resize(0);
                return;
            }
            const Eigen::MatrixXd H = Z.transpose() * K * Z;
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (H + H.transpose()));
            res.tangent_eigenvalues = eig.eigenvalues();
            const double scale = std::max(1.0, K.cwiseAbs().maxCoeff());
            const double tol = opt.stability_tolerance * scale;
            if (res.tangent_eigenvalues.minCoeff() < -tol)
                res.stability = "unstable";
            else if (res.tangent_eigenvalues.minCoeff() > tol)
                res.stability = "stable";
            else
                res.stability = "neutral";
            return;
        }

        // Large systems: inertia of K + rho A^T A (Finsler), sparse LDL^T.
        Eigen::SparseMatrix<double> K = ev.sparse_blocks();
        K = 0.5 * (Eigen::SparseMatrix<double>(K.transpose()) + K);
        std::vector<Eigen::Triplet<double>> t;
        if (mc > 0)
            for (int c = 0; c < cv.J.outerSize(); ++c)
                for (Eigen::SparseMatrix<double>::InnerIterator it(cv.J, c); it; ++it)
                    t.emplace_back(it.row(), it.col(), it.value());
        for (size_t k = 0; k < rows.size(); ++k)
            for (const auto& e : rows[k].grad) t.emplace_back(mc + k, e.first, e.second);
        Eigen::SparseMatrix<double> A(ma, nv);
        A.setFromTriplets(t.begin(), t.end());
        double kmax = 1.0, amax = 1e-300;
        for (int c = 0; c < K.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) kmax = std::max(kmax, std::abs(it.value()));
        for (int c = 0; c < A.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) amax = std::max(amax, std::abs(it.value()));
        const double rho = 1e6 * kmax / (amax * amax);
        Eigen::SparseMatrix<double> P = K + rho * Eigen::SparseMatrix<double>(A.transpose() * A);
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(P);
        res.tangent_dimension = -1;
        if (ldlt.info() != Eigen::Success) {
            res.stability = "neutral";
            return;
        }
        const Eigen::VectorXd D = ldlt.vectorD();
        const double tol = opt.stability_tolerance * kmax;
        if (D.minCoeff() < -tol)
            res.stability = "unstable";
        else if (D.minCoeff() > tol)
            res.stability = "stable";
        else
            res.stability = "neutral";
    }
};

std::unique_ptr<StaticsSolver> make_ipopt_statics(const StaticsSpec&) { return std::make_unique<IpoptStatics>(); }

}  // namespace
}  // namespace mbd::ipopt_plugin

MBD_STATICS_PLUGIN(ipopt, mbd::ipopt_plugin::make_ipopt_statics)
