#include <mbd/data.hpp>

#include "evaluation/coupled_force_jacobians.hpp"

#include <mbd/kit/formulation.hpp>
#include <mbd/sdk/domain_error.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>

namespace mbd {

Data::Data(const Model& model) : poses(model), model_(&model) {
    const int nvb = velocities_per_body(model.dimension);
    size_t widest = 1, widest_varying = 1;  // the widest element; the widest whose load varies
    for (const ForceInstance& f : model.forces) {
        widest = std::max(widest, f.bodies.size());
        // an element with couplings differences two bodies at a time (coupled_force_jacobians.hpp)
        if (!f.constant_load && !force_couplings(f)) widest_varying = std::max(widest_varying, f.bodies.size());
    }
    for (const JointInstance& j : model.joints) widest = std::max(widest, j.bodies.size());
    view.planar_bodies.reserve(widest);
    view.spatial_bodies.reserve(widest);
    const int n = nvb * static_cast<int>(widest), n_varying = nvb * static_cast<int>(widest_varying);
    force_Q.setZero(n);
    joint_gamma_gradient.setZero(n);
    force_plus.setZero(n_varying);
    force_minus.setZero(n_varying);
    force_dQ_dq.setZero(n_varying, n_varying);
    force_dQ_dv.setZero(n_varying, n_varying);
    probe.q.setZero(model.nq());
    probe.v.setZero(model.nv());
    for (const JointInstance& j : model.joints) {
        ConstraintEval eval;
        eval.resize(j.joint->rows(), nvb * static_cast<int>(j.bodies.size()));
        joint_rows.push_back(std::move(eval));
        VelocityConstraintEval velocity;
        velocity.resize(j.joint->velocity_rows(), nvb * static_cast<int>(j.bodies.size()));
        joint_velocity_rows.push_back(std::move(velocity));
    }
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        flexible_q.push_back(Eigen::VectorXd::Zero(f.size));
        flexible_v.push_back(Eigen::VectorXd::Zero(f.size));
    }
    auto slots_of = [&](const std::vector<FlexibleAttachment>& attachments, int rows) {
        std::vector<FlexibleSlot> slots(attachments.size());
        for (size_t a = 0; a < attachments.size(); ++a) {
            const int n = model.flexible_bodies[attachments[a].body].size;
            slots[a].J.setZero(rows, n);
        }
        return slots;
    };
    for (const JointInstance& j : model.joints) joint_flexible.push_back(slots_of(j.flexible, j.joint->rows()));
    for (const Driver& d : model.drivers) driver_flexible.push_back(slots_of(model.joints[d.joint].flexible, 1));
    for (const ForceInstance& f : model.forces) force_flexible.push_back(slots_of(f.flexible, 0));
    posed_q_.setZero(model.nq());
    posed_v_.setZero(model.nv());
    for (const Driver& d : model.drivers) {
        CoordinateEval eval;
        eval.J.setZero(nvb * static_cast<int>(model.joints[d.joint].bodies.size()));
        driver_rows.push_back(std::move(eval));
    }
}

void Data::pose(const State& state) {
    const bool sized = state.q.size() == posed_q_.size() && state.v.size() == posed_v_.size();
    if (posed_ && sized && state.q == posed_q_) {
        // the same positions: the rotation matrices hold; only new velocities (the probes of a
        // velocity derivative, jdot_transpose.hpp, evaluate many velocities at one position)
        if (state.v == posed_v_) return;
        poses.update_velocities(state);
        pose_flexible(state);
        posed_v_ = state.v;
        return;
    }
    poses.update(state);
    pose_flexible(state);
    posed_ = sized;
    if (posed_) {
        posed_q_ = state.q;
        posed_v_ = state.v;
    }
}

void Data::pose_flexible(const State& state) {
    const std::vector<FlexibleBodyInstance>& bodies = model_->flexible_bodies;
    for (size_t k = 0; k < bodies.size(); ++k) {
        flexible_q[k] = state.q.segment(bodies[k].offset, bodies[k].size);
        flexible_v[k] = state.v.segment(bodies[k].v_offset, bodies[k].size);
    }
}

void Data::fill_view(BodyList bodies, const std::vector<FlexibleAttachment>& attachments,
                     std::vector<FlexibleSlot>& slots, double t) {
    poses.fill(bodies, t, view);
    const bool planar = model_->dimension == Dimension::Planar;
    for (size_t a = 0; a < attachments.size(); ++a) {
        const FlexibleAttachment& at = attachments[a];
        MaterialFrame& frame = slots[a].frame;
        const FlexibleBodyInstance& body = model_->flexible_bodies[at.body];
        try {
            body.body->frame(flexible_q[at.body], flexible_v[at.body], at.xi.data(), frame);
        } catch (const DomainError& outside) {
            // the body's plugin says where its material frame ceased to exist: name the body and the time
            throw DynamicsError(t, "flexible body '" + body.name + "' (type " + body.type +
                                       (body.where.empty() ? "" : ", " + body.where) +
                                       "): its material frame at a joint or force point is undefined at t = " +
                                       format_time(t) + ": " + outside.what());
        }
        if (planar)
            view.planar_bodies[at.slot] = &frame.planar;
        else
            view.spatial_bodies[at.slot] = &frame.spatial;
    }
}

}  // namespace mbd
