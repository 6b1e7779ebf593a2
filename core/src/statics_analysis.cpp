// Statics and inverse dynamics over a Model (see statics_analysis.hpp).
#include <mbd/statics_analysis.hpp>

#include <mbd/kinematics.hpp>
#include <mbd/sdk/formulation.hpp>
#include <mbd/sdk/reactions.hpp>

#include <yaml-cpp/yaml.h>

#include "scene_source.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <limits>
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

JointLoad load_of(const JointReaction& r) {
    JointLoad out;
    out.name = r.name;
    if (r.on.size() >= 2 && r.on[1].body >= 0) {
        out.force = r.on[1].force;
        out.torque = r.on[1].torque;
    } else if (r.on.size() >= 2) {
        // the second body is the ground: minus the reaction on the others, moved to its point
        const Vec3 P = r.on[1].point;
        for (const BodyReaction& b : r.on) {
            if (b.body < 0) continue;
            out.force -= b.force;
            out.torque -= b.torque + (b.point - P).cross(b.force);
        }
    } else if (!r.on.empty()) {
        out.force = r.on[0].force;
        out.torque = r.on[0].torque;
    }
    return out;
}

}  // namespace

std::vector<JointLoad> joint_loads(const System& system, const State& state, const Eigen::VectorXd& lambda) {
    std::vector<JointLoad> out;
    for (const JointReaction& r : joint_reactions(system, state, lambda)) out.push_back(load_of(r));
    return out;
}

StaticsReport run_statics(const Model& model, Registry& registry, StaticsOptions options, const std::string& solver) {
    StaticsReport report;
    ModelSystem system(model);
    State start = system.initial_state();
    start.t = options.time;
    start.v.setZero(system.nv());
    system.assemble(start, true);
    if (options.limits.empty()) options.limits = scene_joint_limits(model);

    StaticsSpec spec;
    spec.name = solver;
    spec.type = solver;
    std::shared_ptr<StaticsSolver> s = registry.create_statics(spec, "statics solver");
    report.result = s->solve(system, start, options);
    const StaticsResult& r = report.result;
    if (!r.converged) return report;

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
        // an angle (revolute; periodic coordinates) is reported nearest to its value at
        // the start, s_start + wrap(s - s_start), as the body angles; a limited one as the
        // limit row saw it
        if ((ce.periodic || info.type == "revolute") && !limited[j]) {
            const double s0 = coordinate_at(start, j).value;
            s = s0 + std::remainder(s - s0, 2 * M_PI);
        }
        report.coordinates.push_back(s);
    }
    return report;
}

std::string equilibrium_scene(const Model& model, const State& state) {
    YAML::Node root;
    try {
        root = YAML::Load(detail::read_scene_file(model.source));  // within the scene limits
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot re-read the scene " + model.source + " to write the equilibrium: " + e.what());
    }
    YAML::Node bodies = root["bodies"];
    const bool planar = model.dimension == Dimension::Planar;
    for (std::size_t k = 0; k < bodies.size() && static_cast<int>(k) < model.body_count(); ++k) {
        YAML::Node b = bodies[k];
        if (planar) {
            const int o = 3 * static_cast<int>(k);
            YAML::Node pos;
            pos.push_back(state.q[o]);
            pos.push_back(state.q[o + 1]);
            pos.SetStyle(YAML::EmitterStyle::Flow);
            b["position"] = pos;
            b["angle"] = state.q[o + 2];
        } else {
            const int o = 7 * static_cast<int>(k);
            YAML::Node pos, ep, orientation;
            for (int i = 0; i < 3; ++i) pos.push_back(state.q[o + i]);
            for (int i = 0; i < 4; ++i) ep.push_back(state.q[o + 3 + i]);
            pos.SetStyle(YAML::EmitterStyle::Flow);
            ep.SetStyle(YAML::EmitterStyle::Flow);
            orientation["euler_parameters"] = ep;
            orientation.SetStyle(YAML::EmitterStyle::Flow);
            b["position"] = pos;
            b["orientation"] = orientation;
        }
        b.remove("velocity");
        b.remove("angular_velocity");
    }
    // Joint (and world-frame force) points and axes describe the scene's initial
    // configuration: move them with the bodies, from the markers of the first
    // non-ground body, so that the markers stay where they are on the bodies.
    auto pose = [&](int b, Mat3& A, Vec3& R) {
        if (planar) {
            R = Vec3(state.q[3 * b], state.q[3 * b + 1], 0.0);
            A = Mat3::Identity();
            A.topLeftCorner<2, 2>() = planar_rotation(state.q[3 * b + 2]);
        } else {
            R = state.q.segment<3>(7 * b);
            A = rotation_from_euler_parameters(Vec4(state.q.segment<4>(7 * b + 3)).normalized());
        }
    };
    auto list = [&](const Vec3& v) {
        YAML::Node n;
        for (int i = 0; i < (planar ? 2 : 3); ++i) n.push_back(v[i]);
        n.SetStyle(YAML::EmitterStyle::Flow);
        return n;
    };
    auto move_frame = [&](YAML::Node node, const std::vector<int>& element_bodies, const std::vector<Marker>& markers,
                          bool always_point) {
        for (size_t k = 0; k < element_bodies.size() && k < markers.size(); ++k) {
            const int b = element_bodies[k];
            if (b < 0) continue;
            Mat3 A;
            Vec3 R;
            pose(b, A, R);
            Vec3 u = markers[k].u_bar;
            if (planar) u.z() = 0.0;
            if (always_point || node["point"]) node["point"] = list(R + A * u);
            const Mat3 W = planar ? Mat3(A * Eigen::AngleAxisd(markers[k].angle, Vec3::UnitZ()).toRotationMatrix())
                                  : Mat3(A * markers[k].A_bar);
            if (planar) {
                if (node["axis"]) node["axis"] = list(W.col(0));
            } else {
                if (node["axis"]) node["axis"] = list(W.col(2));
                if (node["x_axis"]) node["x_axis"] = list(W.col(0));
                if (node["axes"]) {
                    YAML::Node axes;
                    axes.push_back(list(W.col(2)));
                    axes.push_back(list(W.col(0)));
                    axes.SetStyle(YAML::EmitterStyle::Flow);
                    node["axes"] = axes;
                }
            }
            return;
        }
    };
    if (YAML::Node joints = root["joints"])
        for (std::size_t k = 0; k < joints.size() && k < model.joints.size(); ++k)
            move_frame(joints[k], model.joints[k].bodies, model.joints[k].markers, true);
    if (YAML::Node forces = root["forces"]) {
        const std::size_t offset = model.gravity.isZero(0.0) ? 0 : 1;  // the core's gravity element comes first
        for (std::size_t k = 0; k < forces.size() && k + offset < model.forces.size(); ++k) {
            YAML::Node f = forces[k];
            const ForceInstance& fi = model.forces[k + offset];
            if (fi.bodies.size() >= 2 && !f["points"] && (f["point"] || f["axis"]))
                move_frame(f, fi.bodies, fi.markers, false);
        }
    }

    YAML::Emitter out;
    out.SetDoublePrecision(17);
    out << root;
    return "# static equilibrium of " + model.source + " (mbd statics)\n" + out.c_str() + '\n';
}

void run_inverse(const Model& model, Registry& registry, double t_end, double step, const InverseCallback& callback,
                 InverseOptions options, const std::string& solver) {
    ModelSystem system(model);
    if (options.actuators.empty()) options.actuators = scene_actuators(model);
    if (options.actuators.empty())
        throw InputError(model.source, "inverse dynamics needs actuators: add a top-level 'actuators:' list "
                                       "({name, joint, bounds, weight}; see docs/scene-format.md)");
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

}  // namespace mbd
