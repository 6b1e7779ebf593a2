// Statics and inverse dynamics over a Model (see statics_analysis.hpp).
#include <mbd/statics_analysis.hpp>

#include <mbd/integrator.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/simulation.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/reactions.hpp>
#include <mbd/sdk/text.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

namespace mbd {

std::vector<JointLimit> scene_joint_limits(const Model& model) {
    std::vector<JointLimit> out;
    for (int j = 0; j < static_cast<int>(model.joints.size()); ++j) {
        const JointInstance& joint = model.joints[j];
        if (joint.has_limits) out.push_back({j, joint.limit_lo, joint.limit_hi, joint.limits_where});
    }
    return out;
}

std::vector<ActuatorInfo> scene_actuators(const Model& model) {
    std::vector<ActuatorInfo> out;
    for (const Actuator& a : model.actuators) out.push_back({a.name, a.joint, a.lo, a.hi, a.weight});
    return out;
}

namespace {

// Is the joint's coordinate an angle? Its one relative freedom (relative_motion(), the
// joint's own description of itself) is a rotation or a screw motion.
bool coordinate_is_angle(const Joint& joint) {
    const std::optional<RelativeMotion> motion = joint.relative_motion();
    if (!motion || motion->freedoms.size() != 1) return false;
    const RelativeMotion::Kind kind = motion->freedoms[0].kind;
    return kind == RelativeMotion::Kind::Revolute || kind == RelativeMotion::Kind::Helical;
}

JointLoad load_of(const JointReaction& r) {
    JointLoad out;
    out.name = r.name;
    second_body_load(r, out.force, out.torque);
    return out;
}

}  // namespace

std::vector<JointLoad> joint_loads(System& system, const State& state, const Eigen::VectorXd& lambda) {
    std::vector<JointLoad> out;
    for (const JointReaction& r : joint_reactions(system, state, lambda)) out.push_back(load_of(r));
    return out;
}

namespace {

// The options as docs/statics.md gives them; `mbd statics` checks them as it parses.
void check_statics_options(const StaticsOptions& o) {
    if (!std::isfinite(o.time)) throw InputError("time", "expected a finite number, got " + format_number(o.time));
    if (o.objective != "auto" && o.objective != "potential" && o.objective != "virtual-work")
        throw InputError("objective", "expected 'auto', 'potential' or 'virtual-work', got '" + o.objective + "'");
    if (o.hessian != "exact" && o.hessian != "limited-memory")
        throw InputError("hessian", "expected 'exact' or 'limited-memory', got '" + o.hessian + "'");
    if (!(o.tolerance >= kSmallestTolerance && o.tolerance <= 1.0))
        throw InputError("tolerance", "expected a number from 1e-14 to 1 (below 1e-14 is beneath double-precision "
                                      "round-off), got " + format_number(o.tolerance));
    if (o.max_iterations <= 0)
        throw InputError("max_iterations", "expected a positive number, got " + std::to_string(o.max_iterations));
}

// A joint at a flexible body (model.hpp FlexibleAttachment) has no limit row and no coordinate
// computed through the material frame yet: refused or reported as not computed (NaN). Its
// reaction is computed (mbd/reactions.hpp, the material frame's).
void check_flexible_limits(const Model& model, const std::vector<JointLimit>& limits) {
    for (const JointLimit& l : limits)
        if (l.joint >= 0 && l.joint < static_cast<int>(model.joints.size()) && !model.joints[l.joint].flexible.empty())
            throw InputError(l.where.empty() ? model.joints[l.joint].where : l.where,
                             "joint '" + model.joints[l.joint].name + "' is attached to flexible body '" +
                                 model.flexible_bodies[model.joints[l.joint].flexible.front().body].name +
                                 "', and the statics analysis does not limit such a joint's coordinate; limit a joint "
                                 "between rigid bodies");
}

void mark_flexible_coordinates_not_computed(const Model& model, StaticsReport& report) {
    for (size_t j = 0; j < model.joints.size() && j < report.coordinates.size(); ++j)
        if (!model.joints[j].flexible.empty()) report.coordinates[j] = std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

StaticsReport run_statics(const Model& model, Registry& registry, StaticsOptions options, const std::string& solver) {
    check_statics_options(options);
    // an equilibrium of a nonholonomic system balances the no-slip reactions too (virtual
    // displacements obey A dq = 0), which the statics solvers do not take
    require_holonomic(model, "the statics analysis", "simulate the motion (`mbd simulate`) instead");
    StaticsReport report;
    ModelSystem system(model);
    State start = system.initial_state();
    start.t = options.time;
    start.v.setZero(system.nv());
    system.assemble(start, true);
    if (options.limits.empty()) options.limits = scene_joint_limits(model);
    check_flexible_limits(model, options.limits);

    StaticsSpec spec;
    spec.name = solver;
    spec.type = solver;
    std::shared_ptr<StaticsSolver> s = registry.create_statics(spec, "statics solver");
    report.result = s->solve(system, start, options);
    if (!report.result.converged) return report;
    report.indeterminacy = resolve_indeterminacy(model, system, report.result.state, report.result.lambda);
    const StaticsResult& r = report.result;

    report.reactions = joint_loads(system, r.state, r.lambda);
    for (const JointReaction& d : driver_reactions(system, r.state, r.lambda)) report.driver_efforts.push_back(load_of(d));
    // joint coordinates
    ModelSystem& sys = system;
    BodyStates view;
    const bool planar = model.dimension == Dimension::Planar;
    std::vector<PlanarBody> pb(model.body_count());
    std::vector<SpatialBody> sb(model.body_count());
    PlanarBody pg;
    SpatialBody sg;
    pg.ground = sg.ground = true;
    auto coordinate_at = [&](const State& state, int j) {
        for (int b = 0; b < model.body_count(); ++b) {
            if (planar)
                pb[b].set(state.q.segment<2>(3 * b), state.q[3 * b + 2], Vec2::Zero(), 0.0);
            else
                sb[b].set(state.q.segment<3>(7 * b), state.q.segment<4>(7 * b + 3), Vec3::Zero(), Vec3::Zero());
        }
        const JointInfo& info = sys.joint(j);
        view.t = state.t;
        view.planar_bodies.clear();
        view.spatial_bodies.clear();
        for (int b : info.bodies) {
            if (planar) view.planar_bodies.push_back(b < 0 ? &pg : &pb[b]);
            else view.spatial_bodies.push_back(b < 0 ? &sg : &sb[b]);
        }
        CoordinateEval ce;
        ce.J.setZero(velocities_per_body(model.dimension) * static_cast<int>(info.bodies.size()));
        info.joint->coordinate(view, ce);
        return ce;
    };
    std::vector<bool> limited(sys.joint_count(), false);
    for (const JointLimit& l : options.limits)
        if (l.joint >= 0 && l.joint < sys.joint_count()) limited[l.joint] = true;
    for (int j = 0; j < sys.joint_count(); ++j) {
        const JointInfo& info = sys.joint(j);
        if (!info.joint->has_coordinate()) {
            report.coordinates.push_back(std::numeric_limits<double>::quiet_NaN());
            continue;
        }
        const CoordinateEval ce = coordinate_at(r.state, j);
        double s = ce.value;
        // an angle (a periodic coordinate, or the joint's one freedom is a rotation) is
        // reported nearest to its value at the start, s_start + wrap(s - s_start), as the
        // body angles; a limited one as the limit row saw it
        if ((ce.periodic || coordinate_is_angle(*info.joint)) && !limited[j]) {
            const double s0 = coordinate_at(start, j).value;
            s = s0 + std::remainder(s - s0, 2 * M_PI);
        }
        report.coordinates.push_back(s);
    }
    mark_flexible_coordinates_not_computed(model, report);
    return report;
}

void check_inverse_dynamics(const Model& model, const InverseOptions& options) {
    require_holonomic(model, "inverse dynamics", "simulate the motion (`mbd simulate`) instead");
    if (!model.flexible_bodies.empty())
        throw InputError(model.flexible_bodies.front().where,
                         "flexible body '" + model.flexible_bodies.front().name +
                             "': inverse dynamics prescribes the motion through the drivers, which do not reach a "
                             "flexible body's coordinates; simulate the motion (`mbd simulate`) instead");
    if (options.actuators.empty() && scene_actuators(model).empty())
        throw InputError(model.source, "inverse dynamics needs actuators: add a top-level 'actuators:' list "
                                       "({name, joint, bounds, weight}; see docs/scene-format.md)");
}

void run_inverse(const Model& model, Registry& registry, double t_end, double step, const InverseCallback& callback,
                 InverseOptions options, const std::string& solver) {
    if (options.actuators.empty()) options.actuators = scene_actuators(model);
    check_inverse_dynamics(model, options);
    ModelSystem system(model);
    InverseSpec spec;
    spec.name = solver;
    spec.type = solver;
    std::shared_ptr<InverseSolver> s = registry.create_inverse(spec, "inverse-dynamics solver");
    s->bind(system, options);
    double last_t = 0.0;
    try {
        run_kinematics(model, t_end, step, [&](const State& state, const Eigen::VectorXd& acceleration) {
            last_t = state.t;
            const InverseSample sample = s->solve(state, acceleration);
            return callback ? callback(sample, system) : true;
        });
    } catch (const KinematicsError& e) {
        std::ostringstream m;
        m << "the prescribed motion is unreachable after t = " << last_t << ": " << e.what();
        throw DynamicsError(last_t, m.str());
    }
}

std::vector<std::string> inverse_columns(const Model& model, bool reactions) {
    std::vector<std::string> columns{"t"};
    for (const Actuator& a : model.actuators) columns.push_back(a.name);
    if (reactions)
        for (std::string& c : reaction_columns(model)) columns.push_back(std::move(c));
    return columns;
}

std::vector<double> inverse_row(const InverseSample& sample, System& system, bool reactions) {
    std::vector<double> row{sample.state.t};
    row.insert(row.end(), sample.efforts.data(), sample.efforts.data() + sample.efforts.size());
    if (reactions)
        for (const JointLoad& l : joint_loads(system, sample.state, sample.lambda)) {
            if (system.dimension() == Dimension::Planar) {
                row.insert(row.end(), {l.force.x(), l.force.y(), l.torque.z()});
            } else {
                row.insert(row.end(), {l.force.x(), l.force.y(), l.force.z(), l.torque.x(), l.torque.y(), l.torque.z()});
            }
        }
    return row;
}

}  // namespace mbd
