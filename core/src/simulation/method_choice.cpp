// The automatic choice of formulation and integrator (method_choice.hpp).
#include <mbd/method_choice.hpp>

#include <mbd/contact_scales.hpp>
#include <mbd/integrator.hpp>
#include <mbd/model_system.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/kit/topology.hpp>

#include <Eigen/SparseCholesky>

#include <cmath>

namespace mbd {

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
    // power iteration on M^-1 D: its eigenvalues are real (D symmetric, M positive definite)
    // a start with a component along every mode (all ones would be the rigid motion, which
    // a damper between two bodies does not damp)
    Eigen::VectorXd x(system.nv()), y;
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = std::sin(1.0 + 2.3 * static_cast<double>(i));
    double rate = 0.0;
    for (int k = 0; k < 60; ++k) {
        y = mass.solve(D * x);
        const double norm = y.norm();
        if (!(norm > 0.0) || !std::isfinite(norm)) return std::isfinite(norm) ? rate : 0.0;
        rate = norm / x.norm();
        x = y / norm;
    }
    return rate;
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
    if (!model.flexible_bodies.empty()) {  // only augmented takes them (Formulation::supports_flexible_bodies)
        choice.formulation = "augmented";
        choice.formulation_reason = "flexible body '" + model.flexible_bodies.front().name + "'";
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
    if (stiff && !tree && !reaction_load && model.flexible_bodies.empty() &&
        closure_embedding_possible(system, &closure)) {
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
