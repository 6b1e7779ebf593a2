// Force elements attached to flexible bodies (flexible_forces.hpp).
#include "evaluation/flexible_forces.hpp"

#include <algorithm>

namespace mbd {

void add_flexible_slot_forces(const Model& m, const std::vector<FlexibleAttachment>& attachments,
                              const std::vector<Data::FlexibleSlot>& slots, const Eigen::Ref<const Eigen::VectorXd>& local,
                              Eigen::VectorXd& Q) {
    const int nvb = velocities_per_body(m.dimension);
    for (size_t a = 0; a < attachments.size(); ++a) {
        const FlexibleBodyInstance& body = m.flexible_bodies[attachments[a].body];
        Q.segment(body.v_offset, body.size).noalias() +=
            slots[a].frame.jacobian.transpose() * local.segment(nvb * attachments[a].slot, nvb);
    }
}

double flexible_slot_power(const Model& m, const std::vector<FlexibleAttachment>& attachments,
                           const std::vector<Data::FlexibleSlot>& slots, const Eigen::Ref<const Eigen::VectorXd>& local,
                           const Data& data) {
    const int nvb = velocities_per_body(m.dimension);
    double power = 0.0;
    for (size_t a = 0; a < attachments.size(); ++a)
        power += local.segment(nvb * attachments[a].slot, nvb).dot(slots[a].frame.jacobian *
                                                                   data.flexible_v[attachments[a].body]);
    return power;
}

std::vector<int> element_velocity_columns(const Model& m, const ForceInstance& f) {
    const int nvb = velocities_per_body(m.dimension);
    std::vector<int> columns;
    for (int b : f.bodies)
        if (b != kGround)
            for (int c = 0; c < nvb; ++c) columns.push_back(m.v_offset(b) + c);
    std::vector<int> seen;
    for (const FlexibleAttachment& a : f.flexible) {
        if (std::find(seen.begin(), seen.end(), a.body) != seen.end()) continue;
        seen.push_back(a.body);
        const FlexibleBodyInstance& body = m.flexible_bodies[a.body];
        for (int c = 0; c < body.size; ++c) columns.push_back(body.v_offset + c);
    }
    return columns;
}

void add_flexible_force_jacobians(const Model& m, const ForceInstance& f, const State& state,
                                  const MappedForce& mapped, std::vector<Eigen::Triplet<double>>& dQ_dq,
                                  std::vector<Eigen::Triplet<double>>& dQ_dv) {
    const std::vector<int> columns = element_velocity_columns(m, f);
    const double h = 1e-7;
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(m.nv()), plus, minus;
    State probe;
    for (int col : columns) {
        for (int pass = 0; pass < 2; ++pass) {  // 0: positions, 1: velocities
            for (int sign : {1, -1}) {
                probe = state;
                dv[col] = sign * h;
                if (pass == 0)
                    advance_positions(m, probe.q, dv);
                else
                    probe.v += dv;
                dv[col] = 0.0;
                mapped(probe, sign > 0 ? plus : minus);
            }
            auto& out = pass == 0 ? dQ_dq : dQ_dv;
            for (int row : columns) {
                const double value = (plus[row] - minus[row]) / (2 * h);
                if (value != 0.0) out.emplace_back(row, col, value);
            }
        }
    }
    mapped(state, plus);  // leave the workspace posed at `state`
}

}  // namespace mbd
