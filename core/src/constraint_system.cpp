#include <mbd/constraint_system.hpp>

#include <mbd/sdk/formulation.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <cstdio>

namespace mbd {

namespace {

// The first non-finite entry of a joint's output, described ("C of row 'x' = nan").
std::string first_non_finite(const Joint& joint, const ConstraintEval& e) {
    auto describe = [&](const char* what, int row, double value) {
        return std::string(what) + " of row '" + joint.row_name(row) + "' = " + format_number(value);
    };
    for (int r = 0; r < e.C.size(); ++r) {
        if (!std::isfinite(e.C[r])) return describe("C", r, e.C[r]);
        if (!std::isfinite(e.C_t[r])) return describe("C_t", r, e.C_t[r]);
        if (!std::isfinite(e.gamma[r])) return describe("gamma", r, e.gamma[r]);
        for (int c = 0; c < e.J.cols(); ++c)
            if (!std::isfinite(e.J(r, c))) return describe("the Jacobian", r, e.J(r, c));
    }
    return "no entry";
}

}  // namespace

std::string RowOwner::describe() const {
    if (kind == Kind::Driver) return "driver '" + element_name + "'";
    return "joint '" + element_name + "' (" + row_name + ")";
}

ConstraintSystem::ConstraintSystem(const Model& model, bool include_drivers)
    : model_(&model), include_drivers_(include_drivers), poses_(model) {
    const int nvb = velocities_per_body(model.dimension);
    for (size_t j = 0; j < model.joints.size(); ++j) {
        const JointInstance& ji = model.joints[j];
        const int r = ji.joint->rows();
        joint_offset_.push_back(rows_);
        for (int k = 0; k < r; ++k)
            owners_.push_back({RowOwner::Kind::Joint, static_cast<int>(j), k, ji.name, ji.joint->row_name(k)});
        rows_ += r;
        ConstraintEval eval;
        eval.resize(r, nvb * static_cast<int>(ji.bodies.size()));
        joint_eval_.push_back(std::move(eval));
    }
    joint_rows_ = rows_;
    if (include_drivers_) {
        for (size_t d = 0; d < model.drivers.size(); ++d) {
            const Driver& dr = model.drivers[d];
            owners_.push_back({RowOwner::Kind::Driver, static_cast<int>(d), 0, dr.name, "coordinate"});
            ++rows_;
            CoordinateEval eval;
            eval.J.setZero(nvb * static_cast<int>(model.joints[dr.joint].bodies.size()));
            driver_eval_.push_back(std::move(eval));
        }
    }
}

void ConstraintSystem::evaluate(const State& state, ConstraintValues& out) const {
    const Model& m = *model_;
    const int nvb = velocities_per_body(m.dimension);
    poses_.update(state);
    out.C.resize(rows_);
    out.C_t.resize(rows_);
    out.gamma.resize(rows_);
    triplets_.clear();

    // scatter one row's body blocks into the sparse Jacobian, skipping the ground
    auto scatter = [&](int row, const std::vector<int>& bodies, const auto& row_values) {
        for (size_t b = 0; b < bodies.size(); ++b) {
            if (bodies[b] == kGround) continue;
            const int col0 = m.v_offset(bodies[b]);
            for (int c = 0; c < nvb; ++c) {
                const double value = row_values(nvb * static_cast<int>(b) + c);
                if (value != 0.0) triplets_.emplace_back(row, col0 + c, value);
            }
        }
    };

    for (size_t j = 0; j < m.joints.size(); ++j) {
        const JointInstance& ji = m.joints[j];
        ConstraintEval& e = joint_eval_[j];
        e.C.setZero();
        e.J.setZero();
        e.C_t.setZero();
        e.gamma.setZero();
        poses_.fill(ji.bodies, state.t, view_);
        ji.joint->evaluate(view_, e);
        // a NaN from a joint would surface later as a failed projection or a singular
        // matrix; name the joint here instead (unless the state itself is not finite)
        if (!(e.C.allFinite() && e.C_t.allFinite() && e.gamma.allFinite() && e.J.allFinite()) && state.q.allFinite() &&
            state.v.allFinite())
            throw DynamicsError(state.t, "joint '" + ji.name + "' (type " + ji.type + (ji.where.empty() ? "" : ", " + ji.where) +
                                             ") gave a non-finite value at t = " + format_time(state.t) + " (" +
                                             first_non_finite(*ji.joint, e) +
                                             ") although the body positions and velocities are finite: its equations "
                                             "are undefined in this configuration; check the joint's parameters, or "
                                             "its plugin");
        const int r0 = joint_offset_[j];
        out.C.segment(r0, e.C.size()) = e.C;
        out.C_t.segment(r0, e.C.size()) = e.C_t;
        out.gamma.segment(r0, e.C.size()) = e.gamma;
        for (int r = 0; r < e.C.size(); ++r) scatter(r0 + r, ji.bodies, e.J.row(r));
    }

    if (include_drivers_) {
        for (size_t d = 0; d < m.drivers.size(); ++d) {
            const Driver& dr = m.drivers[d];
            const JointInstance& ji = m.joints[dr.joint];
            CoordinateEval& e = driver_eval_[d];
            e.J.setZero();
            e.gamma = 0.0;
            poses_.fill(ji.bodies, state.t, view_);
            ji.joint->coordinate(view_, e);
            const TimeValue f = dr.motion->evaluate(state.t);
            if (!(std::isfinite(f.f) && std::isfinite(f.df) && std::isfinite(f.ddf)))
                throw DynamicsError(state.t, "driver '" + dr.name + "'" + (dr.where.empty() ? "" : " (" + dr.where + ")") +
                                                 ": its motion is not finite at t = " + format_time(state.t) + " (f = " +
                                                 format_number(f.f) + ", df/dt = " + format_number(f.df) + ", d2f/dt2 = " +
                                                 format_number(f.ddf) +
                                                 "): the time function overflows; check its parameters or shorten "
                                                 "the run");
            // book Sec. 3.6 driving constraints: C = s(q) - f(t), C_t = -fdot, gamma = gamma_s + fddot
            const int row = joint_rows_ + static_cast<int>(d);
            const double residual = e.value - f.f;
            out.C[row] = e.periodic ? wrap_angle(residual) : residual;
            out.C_t[row] = -f.df;
            out.gamma[row] = e.gamma + f.ddf;
            scatter(row, ji.bodies, e.J);
        }
    }

    out.J.resize(rows_, m.nv());
    out.J.setFromTriplets(triplets_.begin(), triplets_.end());
}

}  // namespace mbd
