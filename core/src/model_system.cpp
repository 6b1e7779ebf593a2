#include <mbd/model_system.hpp>

namespace mbd {

ModelSystem::ModelSystem(const Model& model, KinematicsOptions kinematics)
    : model_(&model), kinematics_(kinematics), with_drivers_(model, true), joints_only_(model, false), poses_(model) {
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
    int row = 0;
    for (const JointInstance& j : model.joints) {
        joints_.push_back({j.name, j.type, j.bodies, j.markers, row, j.joint->rows(), j.joint});
        row += j.joint->rows();
    }
    for (const Driver& d : model.drivers) drivers_.push_back({d.name, d.joint, row++});
    for (const ForceInstance& f : model.forces) forces_.push_back({f.name, f.type, f.bodies, f.force});

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
    mass_.resize(model.nv(), model.nv());
    mass_.setFromTriplets(t.begin(), t.end());
}

std::string ModelSystem::describe_row(int row) const { return with_drivers_.owner(row).describe(); }

void ModelSystem::advance_positions(Eigen::VectorXd& q, const Eigen::VectorXd& dv) const {
    mbd::advance_positions(*model_, q, dv);
}

Eigen::VectorXd ModelSystem::coordinate_rates(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
    return mbd::coordinate_rates(*model_, q, v);
}

void ModelSystem::normalize(Eigen::VectorXd& q) const { normalize_euler_parameters(*model_, q); }

namespace {

// Add an element's body-block vector into the system vector, skipping the ground.
void scatter_vector(const Model& m, const std::vector<int>& bodies, const Eigen::VectorXd& local, Eigen::VectorXd& Q) {
    const int nvb = velocities_per_body(m.dimension);
    for (size_t b = 0; b < bodies.size(); ++b)
        if (bodies[b] != kGround) Q.segment(m.v_offset(bodies[b]), nvb) += local.segment(nvb * b, nvb);
}

}  // namespace

void ModelSystem::generalized_forces(const State& state, Eigen::VectorXd& Q) const {
    const Model& m = *model_;
    const int nvb = velocities_per_body(m.dimension);
    Q.setZero(m.nv());
    poses_.update(state);
    for (const ForceInstance& f : m.forces) {
        element_q_.setZero(nvb * static_cast<int>(f.bodies.size()));
        poses_.fill(f.bodies, state.t, view_);
        f.force->evaluate(view_, element_q_);
        scatter_vector(m, f.bodies, element_q_, Q);
    }
    if (m.dimension == Dimension::Spatial) {
        // gyroscopic moment in body axes, -wbar x (Jbar wbar) (book Eq. 7.155, Q_v)
        for (int k = 0; k < m.body_count(); ++k) {
            const Vec3 w = state.v.segment<3>(m.v_offset(k) + 3);
            Q.segment<3>(m.v_offset(k) + 3) -= w.cross(m.bodies[k].inertia * w);
        }
    }
}

void ModelSystem::force_jacobians(const State& state, Eigen::SparseMatrix<double>& dQ_dq,
                                  Eigen::SparseMatrix<double>& dQ_dv) const {
    const Model& m = *model_;
    const int nvb = velocities_per_body(m.dimension);
    std::vector<Eigen::Triplet<double>> tq, tv;
    auto scatter = [&](const std::vector<int>& bodies, const Eigen::MatrixXd& local,
                       std::vector<Eigen::Triplet<double>>& out) {
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
    };
    poses_.update(state);
    for (const ForceInstance& f : m.forces) {
        const int n = nvb * static_cast<int>(f.bodies.size());
        element_dq_.setZero(n, n);
        element_dv_.setZero(n, n);
        if (f.force->has_jacobians()) {
            poses_.fill(f.bodies, state.t, view_);
            f.force->jacobians(view_, element_dq_, element_dv_);
        } else {
            // central differences over the element's own bodies
            const double h = 1e-7;
            Eigen::VectorXd plus(n), minus(n);
            for (size_t b = 0; b < f.bodies.size(); ++b) {
                if (f.bodies[b] == kGround) continue;
                for (int c = 0; c < nvb; ++c) {
                    const int col = m.v_offset(f.bodies[b]) + c;
                    for (int pass = 0; pass < 2; ++pass) {
                        Eigen::VectorXd dv = Eigen::VectorXd::Zero(m.nv());
                        dv[col] = h;
                        for (int sign : {1, -1}) {
                            State s = state;
                            if (pass == 0)
                                mbd::advance_positions(m, s.q, sign * dv);
                            else
                                s.v += sign * dv;
                            poses_.update(s);
                            poses_.fill(f.bodies, s.t, view_);
                            Eigen::VectorXd& target = sign > 0 ? plus : minus;
                            target.setZero();
                            f.force->evaluate(view_, target);
                        }
                        (pass == 0 ? element_dq_ : element_dv_).col(nvb * b + c) = (plus - minus) / (2 * h);
                    }
                }
            }
            poses_.update(state);
        }
        scatter(f.bodies, element_dq_, tq);
        scatter(f.bodies, element_dv_, tv);
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
    dQ_dq.resize(m.nv(), m.nv());
    dQ_dv.resize(m.nv(), m.nv());
    dQ_dq.setFromTriplets(tq.begin(), tq.end());
    dQ_dv.setFromTriplets(tv.begin(), tv.end());
}

double ModelSystem::kinetic_energy(const State& state) const {
    return 0.5 * state.v.dot(mass_ * state.v);
}

double ModelSystem::potential_energy(const State& state) const {
    double V = 0.0;
    poses_.update(state);
    for (const ForceInstance& f : model_->forces) {
        poses_.fill(f.bodies, state.t, view_);
        V += f.force->potential_energy(view_);
    }
    return V;
}

bool ModelSystem::conservative() const {
    for (const ForceInstance& f : model_->forces)
        if (!f.force->is_conservative()) return false;
    return true;
}

void ModelSystem::constraints(const State& state, ConstraintValues& out, bool include_drivers) const {
    (include_drivers ? with_drivers_ : joints_only_).evaluate(state, out);
}

void ModelSystem::assemble(State& state, bool include_drivers) const {
    assemble_positions(include_drivers ? with_drivers_ : joints_only_, state, kinematics_);
}

void ModelSystem::consistent_velocities(State& state, bool include_drivers) const {
    solve_velocities(include_drivers ? with_drivers_ : joints_only_, state, kinematics_.newton.algebra);
}

}  // namespace mbd
