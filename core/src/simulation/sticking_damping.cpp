// The damping rate of friction elements while they stick (method_choice.hpp).
//
// A regularized Coulomb law (coulomb_law.hpp) has the slope 1.5 mu_s N / v_s inside its
// stiction band, a damping rate of about mu_s N / (v_s m): with v_s = 1e-6 m/s and N = m g
// some 1e7 1/s. The initial state may not show it: a contact that slides at the start is past
// the band, and an element whose load is a joint's reaction (Force::load_joint) is evaluated
// at N = 0 until a formulation solves its load. So the rate is measured where the contact
// sticks: at the initial positions, every velocity zero, each reaction load set to the
// reaction the joint carries under the static load there (the multipliers of
// M vdot + J^T lambda = Q, J vdot = gamma, with the loop between friction and reaction solved
// as a run solves it, reaction_loads.hpp), dQ/dv by central differences with a step well
// inside the narrowest stiction band.
#include <mbd/method_choice.hpp>

#include <mbd/model_system.hpp>
#include <mbd/kit/reaction_loads.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/tolerance_choice.hpp>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <set>

namespace mbd {

namespace {

// Beyond this many constraint rows the static reactions (a dense factorization of
// J M^-1 J^T) are not estimated: reaction-loaded elements then count at the load 0.
constexpr int kLargestReactionEstimate = 2000;

// Sets the System's reaction loads to those the joints carry under the static load at
// `state` (v = 0); returns false (loads left at 0) when they cannot be estimated.
bool set_static_reaction_loads(ModelSystem& system, const State& state) {
    if (system.reaction_loaded_forces().empty()) return false;
    ReactionLoadSolver solver;
    solver.bind(system);
    solver.clear();
    ConstraintValues cv;
    system.constraints(state, cv, true);
    if (cv.J.rows() == 0 || cv.J.rows() > kLargestReactionEstimate) return false;
    Eigen::VectorXd Q;
    system.generalized_forces(state, Q);
    const Eigen::MatrixXd J(cv.J);
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> mass(system.mass_matrix());
    if (mass.info() != Eigen::Success) return false;
    const Eigen::MatrixXd M_inverse_Jt = mass.solve(Eigen::MatrixXd(J.transpose()));
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> S(J * M_inverse_Jt);  // redundant rows: min norm
    const Eigen::VectorXd M_inverse_Q = mass.solve(Q);
    Eigen::VectorXd lambda = S.solve(Eigen::VectorXd(J * M_inverse_Q - cv.gamma));
    try {
        solver.solve(state.t, state, cv.J, Q, lambda,
                     [&](const Eigen::VectorXd& dQ, Eigen::VectorXd& dlambda) {
                         const Eigen::VectorXd M_inverse_dQ = mass.solve(dQ);
                         dlambda = S.solve(Eigen::VectorXd(J * M_inverse_dQ));
                     });
    } catch (const std::exception&) {  // a self-locking element: the run itself names it
        solver.clear();
        return false;
    }
    return system.reaction_loads().allFinite();
}

}  // namespace

StickingDamping sticking_damping_rate(const Model& model) {
    StickingDamping out;
    const std::vector<VelocityScale> scales = velocity_scales(model);
    if (scales.empty() || model.body_count() == 0) return out;
    ModelSystem system(model);
    State state = system.initial_state();
    state.v.setZero(system.nv());
    const bool loads = set_static_reaction_loads(system, state);
    // the velocity columns of the friction elements' bodies
    const int nvb = velocities_per_body(model.dimension);
    std::set<int> bodies;
    for (const VelocityScale& s : scales)
        for (const ForceInstance& f : model.forces)
            if (f.name == s.element)
                for (int b : f.bodies)
                    if (b != kGround) bodies.insert(b);
    std::vector<int> columns;
    for (int b : bodies)
        for (int c = 0; c < nvb; ++c) columns.push_back(model.v_offset(b) + c);
    const int n = static_cast<int>(columns.size());
    if (n == 0) return out;
    double narrowest = scales.front().velocity;
    for (const VelocityScale& s : scales) narrowest = std::min(narrowest, s.velocity);
    const double h = 1e-3 * narrowest;
    Eigen::MatrixXd dQ_dv(n, n), M(n, n);
    Eigen::VectorXd plus, minus;
    for (int c = 0; c < n; ++c) {
        State probe = state;
        probe.v[columns[c]] = h;
        system.generalized_forces(probe, plus);
        probe.v[columns[c]] = -h;
        system.generalized_forces(probe, minus);
        for (int r = 0; r < n; ++r) {
            dQ_dv(r, c) = (plus[columns[r]] - minus[columns[r]]) / (2.0 * h);
            M(r, c) = system.mass_matrix().coeff(columns[r], columns[c]);
        }
    }
    const Eigen::MatrixXd D = -0.5 * (dQ_dv + dQ_dv.transpose());
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eigen(D, M, Eigen::EigenvaluesOnly);
    if (eigen.info() != Eigen::Success || !eigen.eigenvalues().allFinite()) return out;
    out.rate = std::max(0.0, eigen.eigenvalues().maxCoeff());
    out.note = "friction sticking (stiction velocity " + format_number(narrowest) + ")";
    if (loads) {
        const Eigen::VectorXd& N = system.reaction_loads();
        for (size_t k = 0; k < system.reaction_loaded_forces().size(); ++k) {
            const ForceInstance& f = model.forces[system.reaction_loaded_forces()[k]];
            out.note += ", force '" + f.name + "' loaded by joint '" + model.joints[f.load_joint].name +
                        "''s static reaction " + format_number(N[k], 4) + " N";
        }
    }
    return out;
}

}  // namespace mbd
