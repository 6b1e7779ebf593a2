// The statics NLP (statics_nlp.hpp): sizes, bounds, and the evaluations Ipopt calls.
#include "statics_nlp.hpp"

#include <algorithm>
#include <stdexcept>

namespace mbd::ipopt_plugin {
namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr double kInf = 1e19;

// The entries of a sparse matrix as Ipopt asks for them, twice in the same order:
// first their positions (values == nullptr), then their values.
class Entries {
public:
    Entries(Index* iRow, Index* jCol, Number* values) : iRow_(iRow), jCol_(jCol), values_(values) {}
    bool filling() const { return values_ != nullptr; }
    void put(Index row, Index col, double value) {
        if (values_) {
            values_[e_] = value;
        } else {
            iRow_[e_] = row;
            jCol_[e_] = col;
        }
        ++e_;
    }
    // A row over the velocity columns of the blocks `bodies` (Evaluator::offset, size), laid
    // end to end in `row`, with values sign * row: in matrix row `fixed`, or, transposed, in
    // column `fixed` at rows offset + those velocity indices.
    void put_body_row(const Evaluator& ev, const std::vector<int>& bodies, const std::vector<double>& row,
                      double sign, Index fixed, bool transposed = false, Index offset = 0) {
        size_t at = 0;
        for (int b : bodies)
            for (int c = 0; c < ev.size(b); ++c, ++at) {
                const Index v = ev.offset(b) + c;
                const double value = filling() ? sign * row[at] : 0.0;
                if (transposed) put(offset + v, fixed, value);
                else put(fixed, v, value);
            }
    }
    Index count() const { return e_; }

private:
    Index* iRow_;
    Index* jCol_;
    Number* values_;
    Index e_ = 0;
};

}  // namespace

StaticsNLP::StaticsNLP(Evaluator& ev, const Eigen::VectorXd& q0, const std::vector<JointLimit>& limits,
                       bool potential, bool exact_hessian, const Eigen::VectorXd& tail0,
                       const Eigen::VectorXd& x_bound)
    : ev_(ev), q0_(q0), limits_(limits), potential_(potential), exact_(exact_hessian && potential), nv_(ev.nv),
      mc_(ev.mc), nl_(static_cast<int>(limits.size())), lambda0_(tail0), x_bound_(x_bound) {
    n_ = potential_ ? nv_ : nv_ + mc_ + 2 * nl_;
    m_ = potential_ ? mc_ + nl_ : mc_ + nv_ + nl_;
    off_s_ = potential_ ? mc_ : mc_ + nv_;
    for (const auto& rb : ev_.row_bodies) ncj_ += ev_.width(rb);
    for (const auto& cb : ev_.coordinate_bodies) nsj_ += ev_.width(cb);
    for (int a = 0; a < ev_.nblocks; ++a)
        for (int b : ev_.adjacency[a]) {
            nblock_ += ev_.size(a) * ev_.size(b);
            if (b < a) nh_ += ev_.size(a) * ev_.size(b);
            if (b == a) nh_ += ev_.size(a) * (ev_.size(a) + 1) / 2;
        }
}

bool StaticsNLP::get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) {
    n = n_;
    m = m_;
    nnz_jac_g = ncj_ + nsj_ + (potential_ ? 0 : nblock_ + ncj_ + 2 * nsj_);
    nnz_h_lag = exact_ ? nh_ : 0;
    style = C_STYLE;
    return true;
}

bool StaticsNLP::get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) {
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

bool StaticsNLP::get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index,
                                    bool init_lambda, Number*) {
    if (init_z || init_lambda) return false;
    if (init_x) {
        for (Index i = 0; i < n; ++i) x[i] = 0.0;
        if (!potential_)
            for (int r = 0; r < n - nv_ && r < lambda0_.size(); ++r) x[nv_ + r] = lambda0_[r];
    }
    return true;
}

bool StaticsNLP::eval_f(Index n, const Number* x, bool new_x, Number& obj) {
    return guard([&] {
        update(x, new_x);
        if (potential_) {
            obj = ev_.sys.potential_energy(ev_.state(q_));
        } else {
            obj = 0.0;
            for (int k = 0; k < nl_; ++k)
                obj += x[nv_ + mc_ + k] * (s_[k].value - limits_[k].lo) +
                       x[nv_ + mc_ + nl_ + k] * (limits_[k].hi - s_[k].value);
        }
        (void)n;
    });
}

bool StaticsNLP::eval_grad_f(Index n, const Number* x, bool new_x, Number* grad) {
    return guard([&] {
        update(x, new_x);
        for (Index i = 0; i < n; ++i) grad[i] = 0.0;
        if (potential_) {
            for (int b = 0; b < ev_.nblocks; ++b) {
                Eigen::VectorXd row = -Q_.segment(ev_.offset(b), ev_.size(b));
                ev_.times_T(b, row.data());
                for (int c = 0; c < ev_.size(b); ++c) grad[ev_.offset(b) + c] = row[c];
            }
            return;
        }
        for (int k = 0; k < nl_; ++k) {
            const double w = x[nv_ + mc_ + k] - x[nv_ + mc_ + nl_ + k];
            const std::vector<double> row = coordinate_row(k);
            size_t at = 0;
            for (int b : ev_.coordinate_bodies[k])
                for (int c = 0; c < ev_.size(b); ++c) grad[ev_.offset(b) + c] += w * row[at++];
            grad[nv_ + mc_ + k] = s_[k].value - limits_[k].lo;
            grad[nv_ + mc_ + nl_ + k] = limits_[k].hi - s_[k].value;
        }
    });
}

bool StaticsNLP::eval_g(Index, const Number* x, bool new_x, Index m, Number* g) {
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

bool StaticsNLP::eval_jac_g(Index, const Number* x, bool new_x, Index, Index nele, Index* iRow, Index* jCol,
                            Number* values) {
    return guard([&] {
        Entries out(iRow, jCol, values);
        const bool fill = out.filling();
        if (fill) update(x, new_x);
        const std::vector<double> none;
        // C rows: J T
        for (int r = 0; r < mc_; ++r)
            out.put_body_row(ev_, ev_.row_bodies[r], fill ? constraint_row(r) : none, 1.0, r);
        if (!potential_) {
            // R rows, x columns: (dQ/dq - d(J^T lambda + J_s^T nu)/dq) T
            if (fill) {
                ev_.clear_blocks();
                ev_.add_force_jacobian(q_, 1.0);
                ev_.add_constraint_curvature(q_, lambda_of(x), nu_of(x), -1.0);
            }
            for (int a = 0; a < ev_.nblocks; ++a)
                for (size_t k = 0; k < ev_.adjacency[a].size(); ++k) {
                    const int b = ev_.adjacency[a][k];
                    Eigen::MatrixXd B;
                    if (fill) B = right_T(ev_.blocks[a][k], b);
                    for (int i = 0; i < ev_.size(a); ++i)
                        for (int j = 0; j < ev_.size(b); ++j)
                            out.put(mc_ + ev_.offset(a) + i, ev_.offset(b) + j, fill ? B(i, j) : 0.0);
                }
            // R rows, lambda columns: -J^T
            for (int r = 0; r < mc_; ++r)
                out.put_body_row(ev_, ev_.row_bodies[r], fill ? raw_constraint_row(r) : none, -1.0, nv_ + r, true,
                                 mc_);
            // R rows, mu columns: +J_s^T (mu_lo), -J_s^T (mu_hi)
            for (int side = 0; side < 2; ++side)
                for (int k = 0; k < nl_; ++k)
                    out.put_body_row(ev_, ev_.coordinate_bodies[k], fill ? raw_coordinate_row(k) : none,
                                     side == 0 ? 1.0 : -1.0, nv_ + mc_ + side * nl_ + k, true, mc_);
        }
        // limit rows: J_s T
        for (int k = 0; k < nl_; ++k)
            out.put_body_row(ev_, ev_.coordinate_bodies[k], fill ? coordinate_row(k) : none, 1.0, off_s_ + k);
        if (out.count() != nele) throw std::logic_error("Jacobian size mismatch");
    });
}

bool StaticsNLP::eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda, bool,
                        Index nele, Index* iRow, Index* jCol, Number* values) {
    if (!exact_) return false;
    return guard([&] {
        Entries out(iRow, jCol, values);
        const bool fill = out.filling();
        if (fill) {
            update(x, new_x);
            ev_.clear_blocks();
            if (obj_factor != 0.0) ev_.add_force_jacobian(q_, -obj_factor);
            Eigen::VectorXd lam = Eigen::Map<const Eigen::VectorXd>(lambda, mc_);
            Eigen::VectorXd nu = Eigen::Map<const Eigen::VectorXd>(lambda + mc_, nl_);
            ev_.add_constraint_curvature(q_, lam, nu, 1.0);
        }
        for (int a = 0; a < ev_.nblocks; ++a)
            for (size_t k = 0; k < ev_.adjacency[a].size(); ++k) {
                const int b = ev_.adjacency[a][k];
                if (b > a) continue;
                Eigen::MatrixXd S;
                if (fill) {
                    const Eigen::MatrixXd Hab = left_T(right_T(ev_.blocks[a][k], b), a);
                    const Eigen::MatrixXd Hba = left_T(right_T(ev_.blocks[b][ev_.block_index(b, a)], a), b);
                    S = 0.5 * (Hab + Hba.transpose());
                }
                for (int i = 0; i < ev_.size(a); ++i)
                    for (int j = 0; j < ev_.size(b); ++j) {
                        if (b == a && j > i) continue;
                        out.put(ev_.offset(a) + i, ev_.offset(b) + j, fill ? S(i, j) : 0.0);
                    }
            }
        if (out.count() != nele) throw std::logic_error("Hessian size mismatch");
    });
}

void StaticsNLP::finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number*, const Number*,
                                   Index m, const Number*, const Number* lambda, Number,
                                   const Ipopt::IpoptData* ip_data, Ipopt::IpoptCalculatedQuantities*) {
    solver_status = status;
    x_final = Eigen::Map<const Eigen::VectorXd>(x, n);
    g_multipliers = Eigen::Map<const Eigen::VectorXd>(lambda, m);
    if (ip_data) iterations = ip_data->iter_count();
    finalized = true;
}

void StaticsNLP::update(const Number* x, bool new_x) {
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

Eigen::VectorXd StaticsNLP::nu_of(const Number* x) const {
    Eigen::VectorXd nu(nl_);
    for (int k = 0; k < nl_; ++k) nu[k] = x[nv_ + mc_ + nl_ + k] - x[nv_ + mc_ + k];
    return nu;
}

Eigen::VectorXd StaticsNLP::residual_vector(const Number* x) const {
    Eigen::VectorXd R = Q_;
    if (mc_ > 0) R -= cv_.J.transpose() * lambda_of(x);
    const Eigen::VectorXd nu = nu_of(x);
    for (int k = 0; k < nl_; ++k)
        for (const auto& e : s_[k].grad) R[e.first] -= e.second * nu[k];
    return R;
}

// Where column `column` lands in a row laid over the blocks `bodies` end to end; -1 outside them.
int StaticsNLP::row_position(const std::vector<int>& bodies, int column) const {
    const int b = ev_.block_of(column);
    int at = 0;
    for (int a : bodies) {
        if (a == b) return at + column - ev_.offset(b);
        at += ev_.size(a);
    }
    return -1;
}

std::vector<double> StaticsNLP::raw_constraint_row(int r) const {
    const auto& bodies = ev_.row_bodies[r];
    std::vector<double> row(ev_.width(bodies), 0.0);
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Jrow_, r); it; ++it) {
        const int at = row_position(bodies, static_cast<int>(it.col()));
        if (at >= 0) row[at] = it.value();
    }
    return row;
}

std::vector<double> StaticsNLP::constraint_row(int r) const {
    return times_T(ev_.row_bodies[r], raw_constraint_row(r));
}

std::vector<double> StaticsNLP::raw_coordinate_row(int k) const {
    const auto& bodies = ev_.coordinate_bodies[k];
    std::vector<double> row(ev_.width(bodies), 0.0);
    for (const auto& e : s_[k].grad) {
        const int at = row_position(bodies, e.first);
        if (at >= 0) row[at] += e.second;
    }
    return row;
}

std::vector<double> StaticsNLP::coordinate_row(int k) const {
    return times_T(ev_.coordinate_bodies[k], raw_coordinate_row(k));
}

std::vector<double> StaticsNLP::times_T(const std::vector<int>& bodies, std::vector<double> row) const {
    size_t at = 0;
    for (int b : bodies) {
        ev_.times_T(b, row.data() + at);
        at += ev_.size(b);
    }
    return row;
}

Eigen::MatrixXd StaticsNLP::right_T(const Eigen::MatrixXd& B, int body) const {
    if (ev_.dim == Dimension::Planar || body >= ev_.nb) return B;
    Eigen::MatrixXd out = B;
    out.rightCols<3>() = B.rightCols<3>() * ev_.T[body];
    return out;
}

Eigen::MatrixXd StaticsNLP::left_T(const Eigen::MatrixXd& B, int body) const {
    if (ev_.dim == Dimension::Planar || body >= ev_.nb) return B;
    Eigen::MatrixXd out = B;
    out.bottomRows<3>() = ev_.T[body].transpose() * B.bottomRows<3>();
    return out;
}

}  // namespace mbd::ipopt_plugin
