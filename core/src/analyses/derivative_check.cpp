#include <mbd/derivative_check.hpp>
#include <mbd/sdk/domain_error.hpp>

#include <mbd/body_poses.hpp>

#include <Eigen/Geometry>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mbd {

double DerivativeErrors::worst() const {
    return std::max({jacobian, gamma, time_derivative, coordinate_jacobian, coordinate_gamma, gamma_velocity_transpose, velocity_gamma,
                     velocity_dependence, velocity_jacobian, potential, event_gradient, load_affinity});
}

namespace {

// A smooth trajectory through a random state: every body moves with its own
// sinusoids; spatial orientation is p0 (x) Rx(a(t)) Ry(b(t)) Rz(c(t)).
class Trajectory {
public:
    Trajectory(const Model& model, const State& base, std::mt19937& rng) : model_(model), base_(base) {
        std::uniform_real_distribution<double> amp(-0.4, 0.4), freq(0.5, 2.5), phase(0, 6.283);
        const int n = model.body_count() * 6;
        a_.resize(n);
        w_.resize(n);
        ph_.resize(n);
        for (int k = 0; k < n; ++k) {
            a_[k] = amp(rng);
            w_[k] = freq(rng);
            ph_[k] = phase(rng);
        }
    }

    // value, first and second derivative of the k-th scalar signal
    double f(int k, double t, int derivative = 0) const {
        const double s = std::sin(w_[k] * t + ph_[k]), c = std::cos(w_[k] * t + ph_[k]);
        if (derivative == 0) return a_[k] * s;
        if (derivative == 1) return a_[k] * w_[k] * c;
        return -a_[k] * w_[k] * w_[k] * s;
    }

    State state(double t) const {
        State s = base_;
        s.t = t;
        for (int b = 0; b < model_.body_count(); ++b) {
            const int iq = model_.q_offset(b), iv = model_.v_offset(b);
            if (model_.dimension == Dimension::Planar) {
                for (int c = 0; c < 3; ++c) {
                    s.q[iq + c] = base_.q[iq + c] + f(6 * b + c, t);
                    s.v[iv + c] = f(6 * b + c, t, 1);
                }
            } else {
                for (int c = 0; c < 3; ++c) {
                    s.q[iq + c] = base_.q[iq + c] + f(6 * b + c, t);
                    s.v[iv + c] = f(6 * b + c, t, 1);
                }
                const double al = f(6 * b + 3, t), be = f(6 * b + 4, t), ga = f(6 * b + 5, t);
                Vec4 p = base_.q.segment<4>(iq + 3);
                p = quaternion_product(p, euler_parameters_from_axis_angle(Vec3::UnitX(), al));
                p = quaternion_product(p, euler_parameters_from_axis_angle(Vec3::UnitY(), be));
                p = quaternion_product(p, euler_parameters_from_axis_angle(Vec3::UnitZ(), ga));
                s.q.segment<4>(iq + 3) = p;
                const Mat3 Ry = Eigen::AngleAxisd(be, Vec3::UnitY()).toRotationMatrix();
                const Mat3 Rz = Eigen::AngleAxisd(ga, Vec3::UnitZ()).toRotationMatrix();
                s.v.segment<3>(iv + 3) = (Ry * Rz).transpose() * (f(6 * b + 3, t, 1) * Vec3::UnitX()) +
                                         Rz.transpose() * (f(6 * b + 4, t, 1) * Vec3::UnitY()) +
                                         f(6 * b + 5, t, 1) * Vec3::UnitZ();
            }
        }
        return s;
    }

    // vdot by a fourth-order central difference of v(t) (exact enough as an oracle input)
    Eigen::VectorXd acceleration(double t) const {
        const double h = 1e-3;
        return (state(t - 2 * h).v - 8 * state(t - h).v + 8 * state(t + h).v - state(t + 2 * h).v) / (12 * h);
    }

private:
    const Model& model_;
    State base_;
    std::vector<double> a_, w_, ph_;
};

std::string describe(const Model& model, const State& s) {
    std::ostringstream out;
    out.precision(6);
    out << "t = " << s.t;
    for (int b = 0; b < model.body_count(); ++b) {
        out << "; " << model.bodies[b].name << " q = [" << s.q.segment(model.q_offset(b), coordinates_per_body(model.dimension)).transpose()
            << "] v = [" << s.v.segment(model.v_offset(b), velocities_per_body(model.dimension)).transpose() << "]";
    }
    return out.str();
}

// The states of the checks: a random state near the scene's configuration.
State random_check_state(const Model& model, std::mt19937& rng) { return random_state(model, rng, 0.3, 3.0, 0.37); }

// Relative error of a against b with a floor so that zero entries do not divide by zero.
double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - b).norm() / std::max(1.0, b.norm());
}

// A YAML flow sequence of numbers written with all their digits.
YAML::Node yaml_vector(const Eigen::VectorXd& x) {
    YAML::Node node(YAML::NodeType::Sequence);
    node.SetStyle(YAML::EmitterStyle::Flow);
    for (int k = 0; k < x.size(); ++k) {
        std::ostringstream text;
        text.precision(17);
        text << x[k];
        node.push_back(text.str());
    }
    return node;
}

}  // namespace

State random_state(const Model& model, std::mt19937& rng, double spread, double velocity_factor, double t) {
    State base = model.initial_state();
    std::normal_distribution<double> noise(0.0, spread);
    Eigen::VectorXd jolt(model.nv());
    for (int k = 0; k < jolt.size(); ++k) jolt[k] = noise(rng);
    advance_positions(model, base.q, jolt);
    for (int k = 0; k < base.v.size(); ++k) base.v[k] = velocity_factor * noise(rng);
    base.t = t;
    return base;
}

std::string with_random_joint_geometry(const std::string& scene_yaml, std::mt19937& rng) {
    YAML::Node root = YAML::Load(scene_yaml);
    const bool planar = !(root["dimension"] && root["dimension"].as<std::string>() == "spatial");
    const int dim = planar ? 2 : 3;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto random_vector = [&](double size) {
        Eigen::VectorXd x(dim);
        for (int k = 0; k < dim; ++k) x[k] = size * u(rng);
        return x;
    };
    auto random_direction = [&]() {
        Eigen::VectorXd x;
        do x = random_vector(1.0);
        while (x.norm() < 0.2);
        return Eigen::VectorXd(x.normalized());
    };
    YAML::Node joints = root["joints"];
    if (!joints || !joints.IsSequence()) return scene_yaml;
    for (YAML::Node joint : joints) {
        if (!joint.IsMap()) continue;
        joint["point"] = yaml_vector(random_vector(1.0));
        if (joint["points"] && joint["points"].IsSequence()) {
            YAML::Node points(YAML::NodeType::Sequence);
            for (size_t k = 0; k < joint["points"].size(); ++k) points.push_back(yaml_vector(random_vector(0.5)));
            joint["points"] = points;
        }
        if (!planar && joint["axes"]) {
            const Eigen::Vector3d a1 = random_direction();
            const Eigen::Vector3d a2 = a1.cross(Eigen::Vector3d(random_direction())).normalized();
            YAML::Node axes(YAML::NodeType::Sequence);
            axes.push_back(yaml_vector(a1));
            axes.push_back(yaml_vector(a2));
            joint["axes"] = axes;
            continue;
        }
        const Eigen::VectorXd axis = random_direction();
        joint["axis"] = yaml_vector(axis);
        if (!planar && joint["x_axis"]) {
            const Eigen::Vector3d z = axis;
            joint["x_axis"] = yaml_vector(z.cross(Eigen::Vector3d(random_direction())).normalized());
        }
    }
    YAML::Emitter out;
    out << root;
    return std::string(out.c_str()) + "\n";
}

namespace {

// One joint of a model evaluated at a state: its constraint rows and coordinate,
// over the velocity columns of its bodies (ground columns are not compared).
class JointProbe {
public:
    JointProbe(const Model& model, const JointInstance& ji)
        : model(model), ji(ji), nvb(velocities_per_body(model.dimension)),
          cols(nvb * static_cast<int>(ji.bodies.size())), poses_(model) {}

    void eval(const State& s) {
        poses_.update(s);
        e.resize(ji.joint->rows(), cols);
        ji.joint->evaluate(poses_.view(ji.bodies, s.t), e);
        ce = CoordinateEval{};
        ce.J.setZero(cols);
        if (ji.joint->has_coordinate()) ji.joint->coordinate(poses_.view(ji.bodies, s.t), ce);
        ve.resize(ji.joint->velocity_rows(), cols);
        if (ve.b.size()) ji.joint->evaluate_velocity(poses_.view(ji.bodies, s.t), ve);
    }
    // A v - b of the velocity-level rows at a state
    Eigen::VectorXd velocity_residual(const State& s) {
        eval(s);
        Eigen::MatrixXd A = ve.A;
        zero_ground_columns(A);
        return A * joint_entries(s.v) - ve.b;
    }
    // The state perturbed along velocity direction dv (exponential map for rotations).
    State moved(const State& s, const Eigen::VectorXd& dv) const {
        State out = s;
        advance_positions(model, out.q, dv);
        return out;
    }
    // The joint's entries of a model velocity vector (zero for ground).
    Eigen::VectorXd joint_entries(const Eigen::VectorXd& all) const {
        Eigen::VectorXd v = Eigen::VectorXd::Zero(cols);
        for (size_t b = 0; b < ji.bodies.size(); ++b)
            if (ji.bodies[b] != kGround) v.segment(nvb * b, nvb) = all.segment(model.v_offset(ji.bodies[b]), nvb);
        return v;
    }
    void zero_ground_columns(Eigen::MatrixXd& J) const {
        for (size_t b = 0; b < ji.bodies.size(); ++b)
            if (ji.bodies[b] == kGround) J.middleCols(nvb * b, nvb).setZero();
    }
    void zero_ground_columns(Eigen::MatrixXd& J, Eigen::RowVectorXd& J_s) const {
        for (size_t b = 0; b < ji.bodies.size(); ++b)
            if (ji.bodies[b] == kGround) {
                J.middleCols(nvb * b, nvb).setZero();
                J_s.segment(nvb * b, nvb).setZero();
            }
    }

    const Model& model;
    const JointInstance& ji;
    const int nvb, cols;
    ConstraintEval e;
    CoordinateEval ce;
    VelocityConstraintEval ve;

private:
    BodyPoses poses_;
};

// The Jacobians J and J_s by central differences of C and s along each velocity
// direction of each moving body (periodic rows and angles unwrapped).
void jacobians_by_differences(JointProbe& p, const State& s, Eigen::MatrixXd& J_fd, Eigen::RowVectorXd& Js_fd) {
    const double h = 1e-6;
    J_fd = Eigen::MatrixXd::Zero(p.e.J.rows(), p.e.J.cols());
    Js_fd = Eigen::RowVectorXd::Zero(p.cols);
    for (size_t b = 0; b < p.ji.bodies.size(); ++b) {
        if (p.ji.bodies[b] == kGround) continue;
        for (int c = 0; c < p.nvb; ++c) {
            Eigen::VectorXd dv = Eigen::VectorXd::Zero(p.model.nv());
            dv[p.model.v_offset(p.ji.bodies[b]) + c] = h;
            p.eval(p.moved(s, dv));
            const Eigen::VectorXd Cp = p.e.C;
            const double sp = p.ce.value;
            p.eval(p.moved(s, -dv));
            Eigen::VectorXd dC = Cp - p.e.C;
            for (int r = 0; r < dC.size(); ++r) {
                const double period = p.ji.joint->row_period(r);
                if (period > 0) dC[r] -= period * std::round(dC[r] / period);
            }
            J_fd.col(p.nvb * b + c) = dC / (2 * h);
            Js_fd[p.nvb * b + c] = p.ji.joint->has_coordinate() ? wrap_angle(sp - p.ce.value) / (2 * h) : 0.0;
        }
    }
}

// C and s at t - 2 ht, t - ht, t + ht, t + 2 ht along the trajectory, periodic rows
// (screw helix) unwrapped around C0.
struct TimeSamples {
    std::pair<Eigen::VectorXd, double> m2, m1, p1, p2;
};
TimeSamples samples_in_time(JointProbe& p, const Trajectory& path, double t, double ht, const Eigen::VectorXd& C0) {
    auto C_at = [&](double tt) {
        p.eval(path.state(tt));
        return std::make_pair(Eigen::VectorXd(p.e.C), p.ce.value);
    };
    TimeSamples out{C_at(t - 2 * ht), C_at(t - ht), C_at(t + ht), C_at(t + 2 * ht)};
    for (int r = 0; r < C0.size(); ++r) {
        const double period = p.ji.joint->row_period(r);
        if (period <= 0) continue;
        for (auto* sample : {&out.m2, &out.m1, &out.p1, &out.p2}) {
            const double d = sample->first[r] - C0[r];
            sample->first[r] = C0[r] + d - period * std::round(d / period);
        }
    }
    return out;
}

// The velocity-level rows at s (on the trajectory, at time t): along the motion
// d/dt (A v - b) = A vdot - gamma (joint.hpp), by a fourth-order central difference; and A, b
// evaluated at other velocities must not change (the rows are linear in v).
void check_velocity_rows(JointProbe& p, const Trajectory& path, const State& s, double t, DerivativeErrors& worst) {
    p.eval(s);
    Eigen::MatrixXd A = p.ve.A;
    p.zero_ground_columns(A);
    const Eigen::VectorXd b = p.ve.b, gamma = p.ve.gamma;
    worst.finite = worst.finite && A.allFinite() && b.allFinite() && gamma.allFinite();
    const double ht = 1e-3;
    const Eigen::VectorXd rate = (p.velocity_residual(path.state(t - 2 * ht)) - 8 * p.velocity_residual(path.state(t - ht)) +
                                  8 * p.velocity_residual(path.state(t + ht)) - p.velocity_residual(path.state(t + 2 * ht))) /
                                 (12 * ht);
    const Eigen::VectorXd gamma_fd = A * p.joint_entries(path.acceleration(t)) - rate;
    worst.velocity_gamma = std::max(worst.velocity_gamma, relative(gamma, gamma_fd));
    State faster = s;
    faster.v = 2.0 * s.v + Eigen::VectorXd::Constant(s.v.size(), 0.7);
    p.eval(faster);
    Eigen::MatrixXd A_faster = p.ve.A;
    p.zero_ground_columns(A_faster);
    worst.velocity_dependence =
        std::max({worst.velocity_dependence, (A_faster - A).norm() / std::max(1.0, A.norm()), relative(p.ve.b, b)});
}

// Joint::gamma_velocity_transpose at s for random row weights, against (d gamma / d v)^T w with
// d gamma / d v by central differences in each velocity of each moving body (exact up to
// round-off for any step: gamma is quadratic in v; a step of the size of v keeps it relative).
void check_gamma_velocity_transpose(JointProbe& p, const State& s, std::mt19937& rng, DerivativeErrors& worst) {
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::VectorXd w(p.ji.joint->rows());
    for (int r = 0; r < w.size(); ++r) w[r] = normal(rng);
    p.eval(s);
    Eigen::VectorXd analytic = Eigen::VectorXd::Zero(p.cols);
    BodyPoses poses(p.model);
    poses.update(s);
    p.ji.joint->gamma_velocity_transpose(poses.view(p.ji.bodies, s.t), w.data(), analytic.data());
    Eigen::VectorXd reference = Eigen::VectorXd::Zero(p.cols);
    const double h = std::max(1.0, s.v.lpNorm<Eigen::Infinity>());
    for (size_t b = 0; b < p.ji.bodies.size(); ++b) {
        if (p.ji.bodies[b] == kGround) {
            analytic.segment(p.nvb * b, p.nvb).setZero();  // ground columns are not compared
            continue;
        }
        for (int c = 0; c < p.nvb; ++c) {
            State probe = s;
            probe.v[p.model.v_offset(p.ji.bodies[b]) + c] += h;
            p.eval(probe);
            const Eigen::VectorXd plus = p.e.gamma;
            probe.v[p.model.v_offset(p.ji.bodies[b]) + c] -= 2.0 * h;
            p.eval(probe);
            reference[p.nvb * b + c] = (plus - p.e.gamma).dot(w) / (2.0 * h);
        }
    }
    worst.finite = worst.finite && analytic.allFinite();
    worst.gamma_velocity_transpose = std::max(worst.gamma_velocity_transpose, relative(analytic, reference));
}

}  // namespace

DerivativeErrors check_joint_derivatives(const Model& model, const JointInstance& ji, std::mt19937& rng, int trials) {
    DerivativeErrors worst;
    JointProbe p(model, ji);
    // a state drawn where the joint's geometry is not defined (a wheel off its rail head: DomainError)
    // checks nothing: it is drawn again, up to 20 times the trials before the error stands
    int outside = 0;
    for (int trial = 0; trial < trials; ++trial) {
        try {
            Trajectory path(model, random_check_state(model, rng), rng);
            const double t = 0.37 + trial;
            const State s = path.state(t);
            p.eval(s);
            const Eigen::VectorXd C0 = p.e.C, gamma = p.e.gamma, C_t = p.e.C_t;
            const Eigen::MatrixXd J = p.e.J;
            const double s0 = p.ce.value, gamma_s = p.ce.gamma;
            const Eigen::RowVectorXd J_s = p.ce.J;

            Eigen::MatrixXd J_fd;
            Eigen::RowVectorXd Js_fd;
            jacobians_by_differences(p, s, J_fd, Js_fd);
            // ground columns are ignored: compare only moving-body columns
            p.zero_ground_columns(J_fd, Js_fd);
            Eigen::MatrixXd J_cmp = J;
            Eigen::RowVectorXd Js_cmp = J_s;
            p.zero_ground_columns(J_cmp, Js_cmp);
            worst.finite = worst.finite && C0.allFinite() && J.allFinite() && gamma.allFinite() && std::isfinite(s0) &&
                           J_s.allFinite() && std::isfinite(gamma_s);
            const double before = worst.worst();
            worst.jacobian = std::max(worst.jacobian, (J_cmp - J_fd).norm() / std::max(1.0, J_fd.norm()));

            // gamma: Cddot along the trajectory by a fourth-order central difference
            const double ht = 1e-3;
            const TimeSamples ts = samples_in_time(p, path, t, ht, C0);
            const auto &m2 = ts.m2, &m1 = ts.m1, &p1 = ts.p1, &p2 = ts.p2;
            const Eigen::VectorXd Cddot =
                (-m2.first + 16 * m1.first - 30 * C0 + 16 * p1.first - p2.first) / (12 * ht * ht);
            const Eigen::VectorXd vdot = p.joint_entries(path.acceleration(t));
            const Eigen::VectorXd gamma_fd = J_cmp * vdot - Cddot;
            worst.gamma = std::max(worst.gamma, relative(gamma, gamma_fd));
            // C_t: Cdot = J v + C_t along the trajectory (book Eq. 3.120)
            const Eigen::VectorXd Cdot = (m2.first - 8 * m1.first + 8 * p1.first - p2.first) / (12 * ht);
            worst.time_derivative = std::max(worst.time_derivative, relative(C_t, Cdot - J_cmp * p.joint_entries(s.v)));

            if (ji.joint->has_coordinate()) {
                worst.coordinate_jacobian = std::max(worst.coordinate_jacobian,
                                                     (Js_cmp - Js_fd).norm() / std::max(1.0, Js_fd.norm()));
                // unwrap the angle samples around s0
                auto unwrap = [&](double x) { return s0 + wrap_angle(x - s0); };
                const double sddot = (-unwrap(m2.second) + 16 * unwrap(m1.second) - 30 * s0 + 16 * unwrap(p1.second) -
                                      unwrap(p2.second)) /
                                     (12 * ht * ht);
                const double gs_fd = Js_cmp.dot(vdot) - sddot;
                worst.coordinate_gamma =
                    std::max(worst.coordinate_gamma, std::abs(gamma_s - gs_fd) / std::max(1.0, std::abs(gs_fd)));
            }
            if (ji.joint->velocity_rows() > 0) check_velocity_rows(p, path, s, t, worst);
            if (ji.joint->has_gamma_velocity_transpose()) check_gamma_velocity_transpose(p, s, rng, worst);
            if (worst.worst() > before) worst.worst_state = describe(model, s);
        } catch (const DomainError&) {
            if (++outside > 20 * trials) throw;
            --trial;
        }
    }
    return worst;
}

namespace {

// One force element evaluated at states of the whole model (its bodies' poses from the state).
struct ForceProbe {
    ForceProbe(const Model& model, const ForceInstance& fi)
        : model(model), fi(fi), nvb(velocities_per_body(model.dimension)),
          n(nvb * static_cast<int>(fi.bodies.size())), events(fi.force->event_count()), poses(model) {}

    Eigen::VectorXd Q(const State& s) {
        poses.update(s);
        Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
        fi.force->evaluate(poses.view(fi.bodies, s.t), out);
        return out;
    }
    double V(const State& s) {
        poses.update(s);
        return fi.force->potential_energy(poses.view(fi.bodies, s.t));
    }
    Eigen::VectorXd g(const State& s) {
        poses.update(s);
        Eigen::VectorXd out = Eigen::VectorXd::Zero(events);
        fi.force->event_values(poses.view(fi.bodies, s.t), out);
        return out;
    }
    // each event's gradient (Force::event_impact) as a row
    Eigen::MatrixXd event_gradients(const State& s) {
        Eigen::MatrixXd G(events, n);
        for (int e = 0; e < events; ++e) {
            Eigen::VectorXd row = Eigen::VectorXd::Zero(n);
            poses.update(s);
            fi.force->event_impact(e, poses.view(fi.bodies, s.t), row);
            G.row(e) = row.transpose();
        }
        return G;
    }

    const Model& model;
    const ForceInstance& fi;
    const int nvb, n, events;
    BodyPoses poses;
};

// The central differences of Q in the positions and velocities, of V and of the event values
// in the positions, column by column of the element's moving bodies.
struct ForceDifferences {
    Eigen::MatrixXd Kq, Kv, G;
    Eigen::VectorXd dV;

    ForceDifferences(ForceProbe& probe, const State& s) {
        const int n = probe.n, nvb = probe.nvb;
        Kq = Kv = Eigen::MatrixXd::Zero(n, n);
        G = Eigen::MatrixXd::Zero(probe.events, n);
        dV = Eigen::VectorXd::Zero(n);
        const double h = 1e-6;
        for (size_t b = 0; b < probe.fi.bodies.size(); ++b) {
            if (probe.fi.bodies[b] == kGround) continue;
            for (int c = 0; c < nvb; ++c) {
                Eigen::VectorXd dv = Eigen::VectorXd::Zero(probe.model.nv());
                dv[probe.model.v_offset(probe.fi.bodies[b]) + c] = h;
                State plus = s, minus = s;
                advance_positions(probe.model, plus.q, dv);
                advance_positions(probe.model, minus.q, -dv);
                const int col = nvb * static_cast<int>(b) + c;
                Kq.col(col) = (probe.Q(plus) - probe.Q(minus)) / (2 * h);
                dV[col] = (probe.V(plus) - probe.V(minus)) / (2 * h);
                if (probe.events) G.col(col) = (probe.g(plus) - probe.g(minus)) / (2 * h);
                plus = s;
                minus = s;
                plus.v += dv;
                minus.v -= dv;
                Kv.col(col) = (probe.Q(plus) - probe.Q(minus)) / (2 * h);
            }
        }
    }
};

// Q(N) must be affine in the load N (Force::evaluate_at_load): the reaction-load solver takes
// G = Q(1) - Q(0) as its direction (kit reaction_loads.hpp), so a curved Q(N) would be solved
// at a wrong load. Second differences at 0, N1, 2 N1.
void check_load_affinity(ForceProbe& probe, const State& s, DerivativeErrors& worst) {
    probe.poses.update(s);
    const double N1 = 10.0;
    Eigen::VectorXd at[3];
    for (int k = 0; k < 3; ++k) {
        at[k] = Eigen::VectorXd::Zero(probe.n);
        probe.fi.force->evaluate_at_load(probe.poses.view(probe.fi.bodies, s.t), k * N1, at[k]);
    }
    worst.finite = worst.finite && at[0].allFinite() && at[1].allFinite() && at[2].allFinite();
    worst.load_affinity =
        std::max(worst.load_affinity, (at[2] - 2.0 * at[1] + at[0]).norm() / std::max(1.0, (at[1] - at[0]).norm()));
}

}  // namespace

DerivativeErrors check_force_derivatives(const Model& model, const ForceInstance& fi, std::mt19937& rng, int trials) {
    DerivativeErrors worst;
    ForceProbe probe(model, fi);
    const int n = probe.n, nvb = probe.nvb;
    for (int trial = 0; trial < trials; ++trial) {
        const State s = random_check_state(model, rng);
        const Eigen::VectorXd Q = probe.Q(s);
        Eigen::MatrixXd G = probe.event_gradients(s);
        worst.finite = worst.finite && Q.allFinite();
        Eigen::MatrixXd Kq = Eigen::MatrixXd::Zero(n, n), Kv = Eigen::MatrixXd::Zero(n, n);
        if (fi.force->has_jacobians()) {
            probe.poses.update(s);
            fi.force->jacobians(probe.poses.view(fi.bodies, s.t), Kq, Kv);
            worst.finite = worst.finite && Kq.allFinite() && Kv.allFinite();
        }
        ForceDifferences fd(probe, s);
        // compare only the moving bodies' rows and columns
        for (size_t b = 0; b < fi.bodies.size(); ++b)
            if (fi.bodies[b] == kGround) {
                for (auto* m : {&Kq, &Kv, &fd.Kq, &fd.Kv}) {
                    m->middleRows(nvb * b, nvb).setZero();
                    m->middleCols(nvb * b, nvb).setZero();
                }
                G.middleCols(nvb * b, nvb).setZero();
                fd.G.middleCols(nvb * b, nvb).setZero();
            }
        const double before = worst.worst();
        if (fi.force->has_jacobians()) {
            worst.jacobian = std::max(worst.jacobian, (Kq - fd.Kq).norm() / std::max(1.0, fd.Kq.norm()));
            worst.velocity_jacobian = std::max(worst.velocity_jacobian, (Kv - fd.Kv).norm() / std::max(1.0, fd.Kv.norm()));
        }
        if (fi.force->is_conservative()) {
            Eigen::VectorXd Qm = Q;
            for (size_t b = 0; b < fi.bodies.size(); ++b)
                if (fi.bodies[b] == kGround) Qm.segment(nvb * b, nvb).setZero();
            worst.potential = std::max(worst.potential, relative(Qm, -fd.dV));
        }
        if (probe.events) {
            worst.finite = worst.finite && G.allFinite();
            worst.event_gradient = std::max(worst.event_gradient, (G - fd.G).norm() / std::max(1.0, fd.G.norm()));
        }
        if (fi.force->is_friction()) check_load_affinity(probe, s, worst);
        if (worst.worst() > before) worst.worst_state = describe(model, s);
    }
    return worst;
}

}  // namespace mbd
