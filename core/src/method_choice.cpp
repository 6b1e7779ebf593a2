// The automatic choice of formulation and integrator (method_choice.hpp).
#include <mbd/method_choice.hpp>

#include <mbd/contact_scales.hpp>
#include <mbd/integrator.hpp>
#include <mbd/model_system.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/sdk/topology.hpp>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>

namespace mbd {

namespace {

// x -> the velocity change the damping load D x gives the constrained system, M y + J^T mu = D x,
// J y = 0: M^-1 D restricted to the motions the joints and drivers allow (an M-orthogonal
// projection). A body's damping rate is that of the mode it can move in: a near-massless body
// between two hinges (the import's frame bodies) moves with its heavy neighbours, not alone.
class ConstrainedDampingOperator {
public:
    ConstrainedDampingOperator(ModelSystem& system, const State& state, Eigen::SparseMatrix<double> D)
        : D_(std::move(D)), nv_(system.mass_matrix().rows()) {
        ConstraintValues cv;
        system.constraints_with_velocity_rows(state, cv, true);
        const Eigen::SparseMatrix<double>& M = system.mass_matrix();
        const Eigen::Index nc = cv.J.rows();
        std::vector<Eigen::Triplet<double>> entries;
        entries.reserve(static_cast<size_t>(M.nonZeros() + 2 * cv.J.nonZeros()));
        for (Eigen::Index c = 0; c < M.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(M, c); it; ++it) entries.emplace_back(it.row(), it.col(), it.value());
        for (Eigen::Index c = 0; c < cv.J.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(cv.J, c); it; ++it) {
                entries.emplace_back(nv_ + it.row(), it.col(), it.value());
                entries.emplace_back(it.col(), nv_ + it.row(), it.value());
            }
        Eigen::SparseMatrix<double> K(nv_ + nc, nv_ + nc);
        K.setFromTriplets(entries.begin(), entries.end());
        K.makeCompressed();
        kkt_.compute(K);
        rhs_.setZero(nv_ + nc);
    }
    // dependent rows (a redundant loop) leave the saddle point singular
    bool ok() const { return kkt_.info() == Eigen::Success; }
    void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
        rhs_.head(nv_) = D_ * x;
        y = kkt_.solve(rhs_).head(nv_);
    }

private:
    Eigen::SparseMatrix<double> D_;
    Eigen::Index nv_;
    Eigen::VectorXd rhs_;
    Eigen::SparseLU<Eigen::SparseMatrix<double>> kkt_;
};

// The largest eigenvalue of `apply` by power iteration (its eigenvalues are real: D symmetric, M
// positive definite), from a start with a component along every mode (all ones would be the
// rigid motion, which a damper between two bodies does not damp).
template <class Apply>
double largest_rate(Eigen::Index n, Apply apply) {
    Eigen::VectorXd x(n), y;
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = std::sin(1.0 + 2.3 * static_cast<double>(i));
    double rate = 0.0;
    for (int k = 0; k < 60; ++k) {
        apply(x, y);
        const double norm = y.norm();
        if (!(norm > 0.0) || !std::isfinite(norm)) return std::isfinite(norm) ? rate : 0.0;
        rate = norm / x.norm();
        x = y / norm;
    }
    return rate;
}

}  // namespace

double fastest_damping_rate(const Model& model) {
    if (model.forces.empty() || model.body_count() == 0) return 0.0;
    ModelSystem system(model);
    const State state = system.initial_state();
    Eigen::SparseMatrix<double> dQ_dq, dQ_dv;
    system.force_jacobians(state, dQ_dq, dQ_dv);
    // the dissipative part: sym(-dQ/dv) (the gyroscopic terms of spatial bodies are skew and
    // dissipate nothing)
    const Eigen::SparseMatrix<double> D = -0.5 * (dQ_dv + Eigen::SparseMatrix<double>(dQ_dv.transpose()));
    if (D.nonZeros() == 0) return 0.0;
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> mass(system.mass_matrix());
    if (mass.info() != Eigen::Success) return 0.0;  // a massless body: the run itself says so
    const Eigen::Index nv = system.mass_matrix().rows();
    // over every body's motion, M^-1 D: an upper bound of the rate over the motions the joints
    // allow (the largest Rayleigh quotient x^T D x / x^T M x over all x bounds that over a
    // subspace), which is kept when the saddle point is singular or ill-conditioned
    const double free_rate = largest_rate(nv, [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y = mass.solve(D * x); });
    ConstrainedDampingOperator constrained(system, state, D);
    if (!constrained.ok()) return free_rate;
    return std::min(free_rate, largest_rate(nv, [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { constrained.apply(x, y); }));
}

ContactFrequency fastest_contact_frequency(const Model& model) {
    ContactFrequency fastest;
    for (const ContactScale& s : contact_scales(model))
        if (s.frequency > fastest.frequency)
            fastest = {s.frequency, "compliant contact '" + s.element + "' oscillating at sqrt(n k delta^(n-1) / m) = " +
                                        format_number(s.frequency, 3) + " rad/s at its penetration (m = " +
                                        format_number(s.mass, 3) + " kg)"};
    return fastest;
}

MethodChoice automatic_method(const Model& model, double t_end) {
    MethodChoice choice;
    ModelSystem system(model);
    std::string topology;
    const bool tree = recursive_embedding_possible(system, &topology);
    choice.formulation = tree ? "embedding" : "augmented";
    choice.formulation_reason = tree ? topology + ": the recursive path of embedding" : topology;
    // only augmented solves a load from a reaction (reaction_loads.hpp)
    const ForceInstance* reaction_load = nullptr;
    for (const ForceInstance& f : model.forces)
        if (f.load_joint >= 0 && !reaction_load) reaction_load = &f;
    if (reaction_load && tree) {
        choice.formulation = "augmented";
        choice.formulation_reason = "force '" + reaction_load->name + "' takes its load from a joint's reaction";
    }
    const double initial_rate = fastest_damping_rate(model);
    const StickingDamping sticking = sticking_damping_rate(model);
    const ContactFrequency contact = fastest_contact_frequency(model);
    double rate = initial_rate;
    std::string what = "fastest damping rate", source;
    if (sticking.rate > rate) {
        rate = sticking.rate;
        source = " (" + sticking.note + ")";
    }
    if (contact.frequency > rate) {
        rate = contact.frequency;
        what = "fastest contact frequency";
        source = " (" + contact.note + ")";
    }
    const double scales = rate * t_end;
    const bool stiff = scales > kStiffDampedTimeScales;
    // stiff with loops: cvode's difference Jacobian costs a rhs per state and its
    // LU the cube of their number, so the fewest states win: the closure path's joint coordinates
    std::string closure;
    if (stiff && !tree && !reaction_load && closure_embedding_possible(system, &closure)) {
        choice.formulation = "embedding";
        choice.formulation_reason = closure + ": the closure path of embedding (stiff: the fewest states for cvode)";
    }
    choice.integrator = automatic_integrator(stiff).name;
    choice.integrator_reason =
        rate > 0.0 ? std::string(stiff ? "stiff" : "not stiff") + ": " + what + " " + format_number(rate, 3) +
                         " 1/s" + source + " over " + format_time(t_end) + " s = " + format_number(scales, 3) +
                         " time scales (" + (stiff ? "above " : "at most ") + format_number(kStiffDampedTimeScales) + ")"
                   : "not stiff: no damping, no compliant contact";
    return choice;
}

}  // namespace mbd
