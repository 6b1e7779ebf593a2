#include <mbd/model_system.hpp>

#include "evaluation/coupled_force_jacobians.hpp"
#include "evaluation/flexible_forces.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace mbd {

ModelSystem::ModelSystem(const Model& model, KinematicsOptions kinematics)
    : model_(&model),
      kinematics_(kinematics),
      with_drivers_(model, true),
      joints_only_(model, false),
      with_drivers_and_velocity_rows_(model, true, true),
      joints_and_velocity_rows_(model, false, true),
      force_bodies_(model.forces),
      data_(model) {
    for (const Body& b : model.bodies) {
        BodyInfo info;
        info.name = b.name;
        info.mass = b.mass;
        info.inertia = b.inertia;
        info.position = b.position;
        if (model.dimension == Dimension::Planar) {
            info.angle = b.angle;
            info.orientation = Eigen::AngleAxisd(b.angle, Vec3::UnitZ()).toRotationMatrix();
        } else {
            info.orientation = rotation_from_euler_parameters(b.euler_parameters.normalized());
        }
        bodies_.push_back(info);
    }
    int row = 0, velocity_row = 0;
    for (const JointInstance& j : model.joints) {
        joints_.push_back({j.name, j.type, j.bodies, j.markers, row, j.joint->rows(), j.joint, velocity_row,
                           j.joint->velocity_rows()});
        row += j.joint->rows();
        velocity_row += j.joint->velocity_rows();
    }
    for (const Driver& d : model.drivers) drivers_.push_back({d.name, d.joint, row++});
    for (const ForceInstance& f : model.forces) {
        const int index = static_cast<int>(forces_.size());
        forces_.push_back({f.name, f.type, f.bodies, f.force, f.load_joint});
        load_slot_.push_back(f.load_joint >= 0 ? static_cast<int>(reaction_loaded_.size()) : -1);
        if (f.load_joint >= 0) reaction_loaded_.push_back(index);
        if (f.force->is_friction()) friction_.push_back(index);
        if (!(f.constant_load && f.load_joint < 0 && f.flexible.empty())) varying_forces_.push_back(index);
    }
    loads_.setZero(static_cast<int>(reaction_loaded_.size()));

    // constant block-diagonal mass matrix
    std::vector<Eigen::Triplet<double>> t;
    for (int k = 0; k < model.body_count(); ++k) {
        const int o = model.v_offset(k);
        const Body& b = model.bodies[k];
        if (model.dimension == Dimension::Planar) {
            t.emplace_back(o, o, b.mass);
            t.emplace_back(o + 1, o + 1, b.mass);
            t.emplace_back(o + 2, o + 2, b.inertia(2, 2));
        } else {
            for (int i = 0; i < 3; ++i) t.emplace_back(o + i, o + i, b.mass);
            for (int i = 0; i < 3; ++i)
                for (int c = 0; c < 3; ++c)
                    if (b.inertia(i, c) != 0.0) t.emplace_back(o + 3 + i, o + 3 + c, b.inertia(i, c));
        }
    }
    // each flexible body's mass matrix at its initial coordinates; one that varies keeps every
    // entry of its block (update_mass_matrix rewrites them in place)
    int widest = 0;
    for (size_t k = 0; k < model.flexible_bodies.size(); ++k) {
        const FlexibleBodyInstance& f = model.flexible_bodies[k];
        Eigen::MatrixXd M;
        f.body->mass_matrix(f.body->initial_coordinates(), M);
        const bool varies = !f.body->constant_mass();
        if (varies) varying_blocks_.push_back({f.v_offset, f.size, f.name}), varying_bodies_.push_back(static_cast<int>(k));
        for (int i = 0; i < f.size; ++i)
            for (int c = 0; c < f.size; ++c)
                if (varies || M(i, c) != 0.0) t.emplace_back(f.v_offset + i, f.v_offset + c, M(i, c));
        widest = std::max(widest, f.size);
    }
    flexible_Q_.setZero(widest);
    mass_.resize(model.nv(), model.nv());
    mass_.setFromTriplets(t.begin(), t.end());
}

std::string ModelSystem::describe_row(int row) const {
    return with_drivers_and_velocity_rows_.owner(row).describe();
}

void ModelSystem::advance_positions(Eigen::VectorXd& q, const Eigen::VectorXd& dv) const {
    mbd::advance_positions(*model_, q, dv);
}

Eigen::VectorXd ModelSystem::coordinate_rates(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
    return mbd::coordinate_rates(*model_, q, v);
}

void ModelSystem::normalize(Eigen::VectorXd& q) const { normalize_euler_parameters(*model_, q); }

namespace {

// Add an element's body-block vector into the system vector, skipping the ground.
// (Bodies: a std::vector<int> or a BodyList)
template <class Bodies>
void scatter_vector(const Model& m, const Bodies& bodies, const Eigen::Ref<const Eigen::VectorXd>& local,
                    Eigen::VectorXd& Q) {
    const int nvb = velocities_per_body(m.dimension);
    for (int b = 0; b < static_cast<int>(bodies.size()); ++b)
        if (bodies[b] != kGround) Q.segment(m.v_offset(bodies[b]), nvb) += local.segment(nvb * b, nvb);
}

// Add an element's body-block matrix into the system's triplets, skipping the ground.
void scatter_matrix(const Model& m, const std::vector<int>& bodies, const Eigen::Ref<const Eigen::MatrixXd>& local,
                    std::vector<Eigen::Triplet<double>>& out) {
    const int nvb = velocities_per_body(m.dimension);
    for (size_t a = 0; a < bodies.size(); ++a) {
        if (bodies[a] == kGround) continue;
        for (size_t b = 0; b < bodies.size(); ++b) {
            if (bodies[b] == kGround) continue;
            for (int i = 0; i < nvb; ++i)
                for (int j = 0; j < nvb; ++j) {
                    const double value = local(nvb * a + i, nvb * b + j);
                    if (value != 0.0) out.emplace_back(m.v_offset(bodies[a]) + i, m.v_offset(bodies[b]) + j, value);
                }
        }
    }
}

}  // namespace

// After data_.pose(state).
Eigen::Ref<Eigen::VectorXd> ModelSystem::element_force(int f, double t) {
    const ForceInstance& force = model_->forces[f];
    const BodyList bodies = force_bodies_[f];
    auto element = data_.force_Q.head(velocities_per_body(model_->dimension) * bodies.size());
    element.setZero();
    data_.fill_view(bodies, force.flexible, data_.force_flexible[f], t);  // a flexible slot: its material frame
    if (load_slot_[f] >= 0)
        force.force->evaluate_at_load(data_.view, loads_[load_slot_[f]], element);
    else
        force.force->evaluate(data_.view, element);
    return element;
}

void ModelSystem::generalized_forces(const State& state, Eigen::VectorXd& Q) {
    const Model& m = *model_;
    // the poses only for what reads them: a scene of constant loads alone (gravity on rigid
    // bodies) adds its stored vector and the gyroscopic moments, which read v
    if (!constant_Q_ready_ || !varying_forces_.empty() || !m.flexible_bodies.empty() || extra_force_)
        data_.pose(state);
    if (!constant_Q_ready_) {  // the constant-load elements once (model.hpp ForceInstance::constant_load)
        constant_Q_.setZero(m.nv());
        for (size_t f = 0; f < m.forces.size(); ++f)
            if (!std::binary_search(varying_forces_.begin(), varying_forces_.end(), static_cast<int>(f)))
                scatter_vector(m, force_bodies_[f], element_force(static_cast<int>(f), state.t), constant_Q_);
        constant_Q_ready_ = true;
    }
    Q = constant_Q_;
    for (const int f : varying_forces_) {
        const auto element = element_force(f, state.t);
        scatter_vector(m, force_bodies_[f], element, Q);
        if (!m.forces[f].flexible.empty())
            add_flexible_slot_forces(m, m.forces[f].flexible, data_.force_flexible[f], element, Q);  // G^T Q_f
    }
    // each flexible body's own forces: elastic, gravity and quadratic-velocity (sdk body.hpp)
    for (size_t k = 0; k < m.flexible_bodies.size(); ++k) {
        const FlexibleBodyInstance& f = m.flexible_bodies[k];
        auto own = flexible_Q_.head(f.size);
        auto target = Q.segment(f.v_offset, f.size);
        f.body->elastic_forces(data_.flexible_q[k], own);
        target += own;
        if (!m.gravity.isZero(0.0)) {
            f.body->gravity_forces(data_.flexible_q[k], m.gravity, own);
            target += own;
        }
        f.body->quadratic_velocity_forces(data_.flexible_q[k], data_.flexible_v[k], own);
        target += own;
    }
    if (extra_force_) extra_force_(state, Q);
    if (m.dimension == Dimension::Spatial) {
        // gyroscopic moment in body axes, -wbar x (Jbar wbar) (book Eq. 7.155, Q_v)
        for (int k = 0; k < m.body_count(); ++k) {
            const Vec3 w = state.v.segment<3>(m.v_offset(k) + 3);
            Q.segment<3>(m.v_offset(k) + 3) -= w.cross(m.bodies[k].inertia * w);
        }
    }
}

void ModelSystem::set_reaction_loads(const Eigen::VectorXd& loads) {
    if (loads.size() != loads_.size())
        throw std::invalid_argument("set_reaction_loads: " + std::to_string(loads.size()) + " loads for " +
                                    std::to_string(loads_.size()) + " reaction-loaded force elements");
    loads_ = loads;
}

void ModelSystem::reaction_load_directions(const State& state, Eigen::MatrixXd& G, std::vector<Vec3>& axes) {
    const Model& m = *model_;
    const int count = static_cast<int>(reaction_loaded_.size());
    G.setZero(m.nv(), count);
    axes.resize(count);
    data_.pose(state);
    for (int k = 0; k < count; ++k) {
        const ForceInstance& f = m.forces[reaction_loaded_[k]];
        const int n = velocities_per_body(m.dimension) * static_cast<int>(f.bodies.size());
        auto one = data_.force_plus.head(n), zero = data_.force_minus.head(n);
        one.setZero();
        zero.setZero();
        data_.poses.fill(f.bodies, state.t, data_.view);
        f.force->evaluate_at_load(data_.view, 1.0, one);  // Q is affine in N: dQ/dN = Q(1) - Q(0)
        f.force->evaluate_at_load(data_.view, 0.0, zero);
        Eigen::VectorXd column = Eigen::VectorXd::Zero(m.nv());
        scatter_vector(m, f.bodies, one - zero, column);
        G.col(k) = column;
        axes[k] = f.force->load_axis(data_.view);
    }
}

double ModelSystem::friction_power(const State& state) {
    const Model& m = *model_;
    const int nvb = velocities_per_body(m.dimension);
    data_.pose(state);
    double power = 0.0;
    for (int f : friction_) {
        const auto element = element_force(f, state.t);
        const std::vector<int>& bodies = m.forces[f].bodies;
        for (size_t b = 0; b < bodies.size(); ++b)
            if (bodies[b] != kGround) power += element.segment(nvb * b, nvb).dot(state.v.segment(m.v_offset(bodies[b]), nvb));
        power += flexible_slot_power(m, m.forces[f].flexible, data_.force_flexible[f], element, data_);
    }
    return power;
}

// One force element's Jacobians by central differences over its own bodies.
void ModelSystem::force_differences(const ForceInstance& f, const State& state, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                                    Eigen::Ref<Eigen::MatrixXd> dQ_dv) {
    const Model& m = *model_;
    const int nvb = velocities_per_body(m.dimension);
    const int n = nvb * static_cast<int>(f.bodies.size());
    const double h = 1e-7;
    auto plus = data_.force_plus.head(n), minus = data_.force_minus.head(n);
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(m.nv());
    for (size_t b = 0; b < f.bodies.size(); ++b) {
        if (f.bodies[b] == kGround) continue;
        for (int c = 0; c < nvb; ++c) {
            const int col = m.v_offset(f.bodies[b]) + c;
            for (int pass = 0; pass < 2; ++pass) {
                for (int sign : {1, -1}) {
                    State& s = data_.probe;
                    s = state;
                    dv[col] = sign * h;
                    if (pass == 0)
                        mbd::advance_positions(m, s.q, dv);
                    else
                        s.v += dv;
                    dv[col] = 0.0;
                    data_.pose(s);
                    data_.poses.fill(f.bodies, s.t, data_.view);
                    auto target = sign > 0 ? plus : minus;
                    target.setZero();
                    f.force->evaluate(data_.view, target);
                }
                (pass == 0 ? dQ_dq : dQ_dv).col(nvb * b + c) = (plus - minus) / (2 * h);
            }
        }
    }
    data_.pose(state);
}

void ModelSystem::force_jacobians(const State& state, Eigen::SparseMatrix<double>& dQ_dq,
                                  Eigen::SparseMatrix<double>& dQ_dv) {
    const Model& m = *model_;
    const int nvb = velocities_per_body(m.dimension);
    std::vector<Eigen::Triplet<double>> tq, tv;
    data_.pose(state);
    for (size_t index = 0; index < m.forces.size(); ++index) {
        const ForceInstance& f = m.forces[index];
        if (f.constant_load) continue;  // zero Jacobians
        if (!f.flexible.empty()) {  // G^T Q_f differenced over the element's columns (flexible_forces.hpp)
            add_flexible_force_jacobians(m, f, state, [&](const State& s, Eigen::VectorXd& Q) {
                Q.setZero(m.nv());
                data_.pose(s);
                const auto element = element_force(static_cast<int>(index), s.t);
                scatter_vector(m, f.bodies, element, Q);
                add_flexible_slot_forces(m, f.flexible, data_.force_flexible[index], element, Q);
            }, tq, tv);
            continue;
        }
        if (const ForceCouplings* couplings = force_couplings(f)) {  // sparse, one coupling at a time
            add_coupled_force_jacobians(m, f, *couplings, state, data_.poses, data_.view, tq, tv);
            continue;
        }
        const int n = nvb * static_cast<int>(f.bodies.size());
        auto element_dq = data_.force_dQ_dq.topLeftCorner(n, n), element_dv = data_.force_dQ_dv.topLeftCorner(n, n);
        element_dq.setZero();
        element_dv.setZero();
        if (f.force->has_jacobians()) {
            data_.poses.fill(f.bodies, state.t, data_.view);
            f.force->jacobians(data_.view, element_dq, element_dv);
        } else {
            force_differences(f, state, element_dq, element_dv);
        }
        scatter_matrix(m, f.bodies, element_dq, tq);
        scatter_matrix(m, f.bodies, element_dv, tv);
    }
    if (m.dimension == Dimension::Spatial) {
        // d/dwbar of -wbar x (J wbar) = skew(J wbar) - skew(wbar) J
        for (int k = 0; k < m.body_count(); ++k) {
            const int o = m.v_offset(k) + 3;
            const Vec3 w = state.v.segment<3>(o);
            const Mat3& J = m.bodies[k].inertia;
            const Mat3 d = skew(J * w) - skew(w) * J;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    if (d(i, j) != 0.0) tv.emplace_back(o + i, o + j, d(i, j));
        }
    }
    // the flexible bodies' elastic stiffness (exact; gravity is constant), and for a body whose
    // mass varies the derivatives of its quadratic-velocity forces (central differences; zero
    // for constant mass)
    for (size_t k = 0; k < m.flexible_bodies.size(); ++k) {
        const FlexibleBodyInstance& f = m.flexible_bodies[k];
        Eigen::MatrixXd K(f.size, f.size);
        f.body->elastic_jacobian(data_.flexible_q[k], K);
        for (int i = 0; i < f.size; ++i)
            for (int c = 0; c < f.size; ++c)
                if (K(i, c) != 0.0) tq.emplace_back(f.v_offset + i, f.v_offset + c, K(i, c));
        if (!f.body->constant_mass()) quadratic_velocity_differences(f, data_.flexible_q[k], data_.flexible_v[k], tq, tv);
    }
    dQ_dq.resize(m.nv(), m.nv());
    dQ_dv.resize(m.nv(), m.nv());
    dQ_dq.setFromTriplets(tq.begin(), tq.end());
    dQ_dv.setFromTriplets(tv.begin(), tv.end());
}

void ModelSystem::quadratic_velocity_differences(const FlexibleBodyInstance& f, const Eigen::VectorXd& q,
                                                 const Eigen::VectorXd& v, std::vector<Eigen::Triplet<double>>& tq,
                                                 std::vector<Eigen::Triplet<double>>& tv) const {
    Eigen::VectorXd plus(f.size), minus(f.size);
    for (int side = 0; side < 2; ++side)  // 0: d/dq, 1: d/dv
        for (int c = 0; c < f.size; ++c) {
            Eigen::VectorXd qp = q, vp = v, qm = q, vm = v;
            const double x = side ? v[c] : q[c], h = 1e-6 * std::max(1.0, std::abs(x));
            (side ? vp : qp)[c] += h;
            (side ? vm : qm)[c] -= h;
            f.body->quadratic_velocity_forces(qp, vp, plus);
            f.body->quadratic_velocity_forces(qm, vm, minus);
            for (int i = 0; i < f.size; ++i) {
                const double d = (plus[i] - minus[i]) / (2 * h);
                if (d != 0.0) (side ? tv : tq).emplace_back(f.v_offset + i, f.v_offset + c, d);
            }
        }
}

void ModelSystem::update_mass_matrix(const Eigen::VectorXd& q) {
    Eigen::MatrixXd M;
    for (size_t k = 0; k < varying_bodies_.size(); ++k) {
        const FlexibleBodyInstance& f = model_->flexible_bodies[varying_bodies_[k]];
        f.body->mass_matrix(q.segment(f.offset, f.size), M);
        for (int c = 0; c < f.size; ++c)  // the block's entries are stored (constructor): no insertion
            for (int i = 0; i < f.size; ++i) mass_.coeffRef(f.v_offset + i, f.v_offset + c) = M(i, c);
    }
}

// 1/2 v^T M(q) v: mass_ for the rigid and constant blocks, each varying block at state.q
double ModelSystem::kinetic_energy(const State& state) const {
    double T = 0.5 * state.v.dot(mass_ * state.v);
    Eigen::MatrixXd M;
    for (size_t k = 0; k < varying_bodies_.size(); ++k) {
        const FlexibleBodyInstance& f = model_->flexible_bodies[varying_bodies_[k]];
        const Eigen::VectorXd v = state.v.segment(f.v_offset, f.size);
        const Eigen::MatrixXd stored(mass_.block(f.v_offset, f.v_offset, f.size, f.size));
        f.body->mass_matrix(state.q.segment(f.offset, f.size), M);
        T += 0.5 * v.dot((M - stored) * v);
    }
    return T;
}

double ModelSystem::potential_energy(const State& state) {
    double V = 0.0;
    data_.pose(state);
    const Model& m = *model_;
    for (size_t f = 0; f < m.forces.size(); ++f) {
        data_.fill_view(force_bodies_[f], m.forces[f].flexible, data_.force_flexible[f], state.t);
        V += m.forces[f].force->potential_energy(data_.view);
    }
    for (size_t k = 0; k < m.flexible_bodies.size(); ++k) {
        const FlexibleBody& body = *m.flexible_bodies[k].body;
        V += body.strain_energy(data_.flexible_q[k]) + body.gravity_potential(data_.flexible_q[k], m.gravity);
    }
    return V;
}

bool ModelSystem::conservative() const {
    for (const ForceInstance& f : model_->forces)
        if (!f.force->is_conservative()) return false;
    return true;
}

void ModelSystem::constraints(const State& state, ConstraintValues& out, bool include_drivers) {
    (include_drivers ? with_drivers_ : joints_only_).evaluate(state, data_, out);
}

void ModelSystem::constraint_gamma(const State& state, Eigen::VectorXd& gamma, bool include_drivers) {
    (include_drivers ? with_drivers_ : joints_only_).evaluate_gamma(state, data_, gamma);
}

void ModelSystem::gamma_velocity_transpose(const State& state, const Eigen::VectorXd& mu, Eigen::VectorXd& out) {
    joints_only_.gamma_velocity_transpose(state, data_, mu, out);
}

void ModelSystem::constraints_with_velocity_rows(const State& state, ConstraintValues& out, bool include_drivers) {
    (include_drivers ? with_drivers_and_velocity_rows_ : joints_and_velocity_rows_).evaluate(state, data_, out);
}

void ModelSystem::assemble(State& state, bool include_drivers) {
    assemble_positions(include_drivers ? with_drivers_ : joints_only_, data_, state, kinematics_);
}

void ModelSystem::consistent_velocities(State& state, bool include_drivers) {
    solve_velocities(include_drivers ? with_drivers_and_velocity_rows_ : joints_and_velocity_rows_, data_, state,
                     kinematics_.newton.algebra);
}

}  // namespace mbd
