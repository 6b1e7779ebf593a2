#include <mbd/constraint_system.hpp>

#include "evaluation/curve_joint.hpp"

#include <mbd/sdk/domain_error.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <initializer_list>
#include <string>
#include <utility>

namespace mbd {

namespace {

// The first non-finite entry of a joint's output, row by row ("C of row 'x' = nan"): the
// per-row vectors in their order, then the row of the matrix.
std::string first_non_finite(const std::function<std::string(int)>& row_name,
                             std::initializer_list<std::pair<const char*, const Eigen::VectorXd*>> vectors,
                             const char* matrix_name, const Eigen::MatrixXd& matrix) {
    auto describe = [&](const char* what, int row, double value) {
        return std::string(what) + " of row '" + row_name(row) + "' = " + format_number(value);
    };
    for (int r = 0; r < matrix.rows(); ++r) {
        for (const auto& [what, v] : vectors)
            if (!std::isfinite((*v)[r])) return describe(what, r, (*v)[r]);
        for (int c = 0; c < matrix.cols(); ++c)
            if (!std::isfinite(matrix(r, c))) return describe(matrix_name, r, matrix(r, c));
    }
    return "no entry";
}

std::string first_non_finite(const Joint& joint, const ConstraintEval& e) {
    return first_non_finite([&](int r) { return joint.row_name(r); }, {{"C", &e.C}, {"C_t", &e.C_t}, {"gamma", &e.gamma}},
                            "the Jacobian", e.J);
}

std::string first_non_finite(const Joint& joint, const VelocityConstraintEval& e) {
    return first_non_finite([&](int r) { return joint.velocity_row_name(r); }, {{"b", &e.b}, {"gamma", &e.gamma}}, "A",
                            e.A);
}

// Every entry of a joint's output finite, given the sum of all its entries. A NaN or an
// infinity in any entry makes the sum non-finite, so the sum decides the common case; only a
// sum that overflowed from finite entries (|entries| near 1e308) needs the entry-by-entry look.
bool rows_finite(const ConstraintEval& e, double sum) {
    if (std::isfinite(sum)) return true;
    return e.C.allFinite() && e.C_t.allFinite() && e.gamma.allFinite() && e.J.allFinite();
}

// A driver's motion must stay where the equations can use it: finite, and below the root of
// the largest double, since a joint squares its rates (omega^2 terms of gamma). A time function
// that grows past that is the driver's fault, not the joint's that overflows on it.
void require_usable_motion(const Driver& driver, const TimeValue& f, double t) {
    const double largest = 1e150;  // sqrt(DBL_MAX) = 1.3e154
    if (std::abs(f.f) <= largest && std::abs(f.df) <= largest && std::abs(f.ddf) <= largest) return;
    const bool finite = std::isfinite(f.f) && std::isfinite(f.df) && std::isfinite(f.ddf);
    throw DynamicsError(t, "driver '" + driver.name + "'" + (driver.where.empty() ? "" : " (" + driver.where + ")") +
                               ": its motion is " + (finite ? "too large for the equations" : "not finite") +
                               " at t = " + format_time(t) + " (f = " + format_number(f.f) + ", df/dt = " +
                               format_number(f.df) + ", d2f/dt2 = " + format_number(f.ddf) +
                               (finite ? "; beyond 1e150 a square overflows" : "") +
                               "): the time function overflows; check its parameters or shorten the run");
}

// A joint along a flexible body's curve (the scene checked that the body implements BodyCurve).
const ConstraintEval& evaluate_along_curve(const Model& model, const CurveJoint& joint, const FlexibleAttachment& curve,
                                          Data& data, Data::FlexibleSlot& slot, ConstraintEval& e) {
    const std::shared_ptr<const FlexibleBody>& body = model.flexible_bodies[curve.body].body;
    slot.J.setZero();
    joint.evaluate_on_curve(data.view, dynamic_cast<const BodyCurve&>(*body), data.flexible_q[curve.body],
                            data.flexible_v[curve.body], e, slot.J);
    return e;
}

}  // namespace

std::string RowOwner::describe() const {
    if (kind == Kind::Driver) return "driver '" + element_name + "'";
    return "joint '" + element_name + "' (" + row_name + ")";
}

ConstraintSystem::ConstraintSystem(const Model& model, bool include_drivers, bool include_velocity_rows)
    : model_(&model),
      include_drivers_(include_drivers),
      include_velocity_rows_(include_velocity_rows),
      joint_bodies_(model.joints) {
    for (const JointInstance& ji : model.joints) {
        joint_.push_back(ji.joint.get());
        flexible_.push_back(&ji.flexible);
    }
    const int nvb = velocities_per_body(model.dimension);
    // the element rows in evaluation order, each with the bodies its Jacobian row spans and the
    // joint's slots on flexible bodies (a driver's row spans its joint's; velocity-level rows have
    // none: the scene refuses them on a joint at a flexible body)
    struct ElementRow {
        int row;
        const std::vector<int>* bodies;
        const std::vector<FlexibleAttachment>* flexible;
    };
    const std::vector<FlexibleAttachment> none;
    std::vector<ElementRow> element_rows;
    for (size_t j = 0; j < model.joints.size(); ++j) {
        const JointInstance& ji = model.joints[j];
        const int r = ji.joint->rows();
        joint_offset_.push_back(rows_);
        for (int k = 0; k < r; ++k) {
            owners_.push_back({RowOwner::Kind::Joint, static_cast<int>(j), k, ji.name, ji.joint->row_name(k)});
            element_rows.push_back({rows_ + k, &ji.bodies, &ji.flexible});
        }
        rows_ += r;
    }
    joint_rows_ = rows_;
    if (include_drivers_) {
        for (size_t d = 0; d < model.drivers.size(); ++d) {
            const Driver& dr = model.drivers[d];
            owners_.push_back({RowOwner::Kind::Driver, static_cast<int>(d), 0, dr.name, "coordinate"});
            element_rows.push_back({rows_, &model.joints[dr.joint].bodies, &model.joints[dr.joint].flexible});
            ++rows_;
        }
    }
    if (include_velocity_rows_) {
        for (size_t j = 0; j < model.joints.size(); ++j) {
            const JointInstance& ji = model.joints[j];
            const int r = ji.joint->velocity_rows();
            velocity_offset_.push_back(rows_);
            for (int k = 0; k < r; ++k) {
                owners_.push_back({RowOwner::Kind::JointVelocity, static_cast<int>(j), k, ji.name,
                                   ji.joint->velocity_row_name(k)});
                element_rows.push_back({rows_ + k, &ji.bodies, &none});
            }
            rows_ += r;
        }
    }
    // the pattern, then each visited entry's place in it
    std::vector<Eigen::Triplet<double>> entries;
    for (const ElementRow& e : element_rows) {
        for (int body : *e.bodies)
            if (body != kGround)
                for (int c = 0; c < nvb; ++c) entries.emplace_back(e.row, model.v_offset(body) + c, 0.0);
        for (const FlexibleAttachment& a : *e.flexible) {
            const FlexibleBodyInstance& f = model.flexible_bodies[a.body];
            for (int c = 0; c < f.size; ++c) entries.emplace_back(e.row, f.v_offset + c, 0.0);
        }
    }
    pattern_.resize(rows_, model.nv());
    pattern_.setFromTriplets(entries.begin(), entries.end());  // a body twice in one element: one entry
    pattern_.makeCompressed();
    slot_.reserve(entries.size());
    for (const Eigen::Triplet<double>& e : entries) {
        const int* begin = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[e.col()];
        const int* end = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[e.col() + 1];
        slot_.push_back(static_cast<int>(std::lower_bound(begin, end, e.row()) - pattern_.innerIndexPtr()));
    }
}

namespace {

// True when J already has exactly this pattern (then only its values are written).
bool has_pattern(const Eigen::SparseMatrix<double>& J, const Eigen::SparseMatrix<double>& pattern) {
    if (J.rows() != pattern.rows() || J.cols() != pattern.cols() || !J.isCompressed() ||
        J.nonZeros() != pattern.nonZeros())
        return false;
    const auto cols = static_cast<size_t>(pattern.cols()) + 1, nnz = static_cast<size_t>(pattern.nonZeros());
    return std::equal(J.outerIndexPtr(), J.outerIndexPtr() + cols, pattern.outerIndexPtr()) &&
           std::equal(J.innerIndexPtr(), J.innerIndexPtr() + nnz, pattern.innerIndexPtr());
}

// A joint whose velocity-level rows are not finite at a finite state.
[[noreturn]] void throw_velocity_rows_not_finite(const JointInstance& ji, const VelocityConstraintEval& e, double t) {
    throw DynamicsError(t, "joint '" + ji.name + "' (type " + ji.type + (ji.where.empty() ? "" : ", " + ji.where) +
                               ") gave a non-finite velocity-level value at t = " + format_time(t) + " (" +
                               first_non_finite(*ji.joint, e) +
                               ") although the body positions and velocities are finite: its equations are "
                               "undefined in this configuration; check the joint's parameters, or its plugin");
}

}  // namespace

struct ConstraintSystem::JacobianScatter {
    double* values;
    const int* slot;
    int nvb;
    // one row's body blocks (a body that appears twice adds up)
    template <class Row>
    void add(BodyList bodies, const Row& row_values) {
        for (int b = 0; b < bodies.size(); ++b) {
            if (bodies[b] == kGround) continue;
            for (int c = 0; c < nvb; ++c) values[*slot++] += row_values(nvb * b + c);
        }
    }
    // one row of J_f G over a flexible body's coordinates
    void add_flexible(const Data::FlexibleSlot& f, int r) {
        for (Eigen::Index c = 0; c < f.J.cols(); ++c) values[*slot++] += f.J(r, c);
    }
};

void ConstraintSystem::evaluate(const State& state, Data& data, ConstraintValues& out) const {
    data.pose(state);
    const Model& m = *model_;
    out.C.resize(rows_);
    out.C_t.resize(rows_);
    out.gamma.resize(rows_);
    if (!has_pattern(out.J, pattern_)) out.J = pattern_;  // once per ConstraintValues
    std::fill(out.J.valuePtr(), out.J.valuePtr() + out.J.nonZeros(), 0.0);
    JacobianScatter scatter{out.J.valuePtr(), slot_.data(), velocities_per_body(m.dimension)};

    // a joint's rows into out at r0, and the sum of all its entries (rows_finite's test, in the same pass)
    auto place = [&](const ConstraintEval& e, int r0, BodyList bodies, const std::vector<Data::FlexibleSlot>& flexible) {
        const int rows = static_cast<int>(e.C.size());
        double sum = 0.0;
        for (int r = 0; r < rows; ++r) {
            out.C[r0 + r] = e.C[r];
            out.C_t[r0 + r] = e.C_t[r];
            out.gamma[r0 + r] = e.gamma[r];
            sum += e.C[r] + e.C_t[r] + e.gamma[r];
        }
        const double* J = e.J.data();
        for (Eigen::Index k = 0; k < e.J.size(); ++k) sum += J[k];
        if (flexible.empty()) {  // rigid bodies only: the common case, kept free of the slots' loop
            for (int r = 0; r < rows; ++r) scatter.add(bodies, e.J.row(r));
            return sum;
        }
        for (int r = 0; r < rows; ++r) {
            scatter.add(bodies, e.J.row(r));
            for (const Data::FlexibleSlot& f : flexible) scatter.add_flexible(f, r);  // J_f G
        }
        return sum;
    };

    for (size_t j = 0; j < m.joints.size(); ++j) {
        const ConstraintEval& e = evaluate_joint(j, state, data);
        // a NaN from a joint would surface later as a failed projection or a singular
        // matrix; name the joint here instead (unless the state itself is not finite)
        if (!rows_finite(e, place(e, joint_offset_[j], joint_bodies_[j], data.joint_flexible[j])))
            throw_if_state_finite(j, e, state);
    }
    const int driver_rows = include_drivers_ ? static_cast<int>(m.drivers.size()) : 0;
    if (driver_rows > 0) evaluate_drivers(state, data, out, scatter);
    if (include_velocity_rows_ && rows_ > joint_rows_ + driver_rows) evaluate_velocity_rows(state, data, out, scatter);
}

void ConstraintSystem::evaluate_drivers(const State& state, Data& data, ConstraintValues& out,
                                        JacobianScatter& J) const {
    const Model& m = *model_;
    for (size_t d = 0; d < m.drivers.size(); ++d) {
        TimeValue f;
        const CoordinateEval& e = evaluate_driver(d, state, data, f);
        // book Sec. 3.6 driving constraints: C = s(q) - f(t), C_t = -fdot, gamma = gamma_s + fddot
        const int row = joint_rows_ + static_cast<int>(d);
        const double residual = e.value - f.f;
        out.C[row] = e.periodic ? wrap_angle(residual) : residual;
        out.C_t[row] = -f.df;
        out.gamma[row] = e.gamma + f.ddf;
        J.add(joint_bodies_[m.drivers[d].joint], e.J);
        for (const Data::FlexibleSlot& slot : data.driver_flexible[d]) J.add_flexible(slot, 0);  // J_f G
    }
}

void ConstraintSystem::evaluate_velocity_rows(const State& state, Data& data, ConstraintValues& out,
                                              JacobianScatter& J) const {
    const Model& m = *model_;
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const JointInstance& ji = m.joints[j];
        VelocityConstraintEval& e = data.joint_velocity_rows[j];
        if (e.b.size() == 0) continue;
        e.A.setZero();
        e.b.setZero();
        e.gamma.setZero();
        data.poses.fill(joint_bodies_[j], state.t, data.view);
        joint_[j]->evaluate_velocity(data.view, e);
        if (!(e.A.allFinite() && e.b.allFinite() && e.gamma.allFinite()) && state.q.allFinite() &&
            state.v.allFinite())
            throw_velocity_rows_not_finite(ji, e, state.t);
        // A v = b as a row without position residual: C = 0, J = A, C_t = -b (kit system.hpp)
        const int r0 = velocity_offset_[j];
        out.C.segment(r0, e.b.size()).setZero();
        out.C_t.segment(r0, e.b.size()) = -e.b;
        out.gamma.segment(r0, e.b.size()) = e.gamma;
        for (int r = 0; r < e.b.size(); ++r) J.add(joint_bodies_[j], e.A.row(r));
    }
}

void ConstraintSystem::evaluate_gamma(const State& state, Data& data, Eigen::VectorXd& gamma) const {
    data.pose(state);
    const Model& m = *model_;
    gamma.resize(joint_rows_ + (include_drivers_ ? static_cast<int>(m.drivers.size()) : 0));
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const ConstraintEval& e = evaluate_joint(j, state, data);
        if (!e.gamma.allFinite()) throw_if_state_finite(j, e, state);
        gamma.segment(joint_offset_[j], e.gamma.size()) = e.gamma;
    }
    if (include_drivers_)
        for (size_t d = 0; d < m.drivers.size(); ++d) {
            TimeValue f;
            gamma[joint_rows_ + static_cast<int>(d)] = evaluate_driver(d, state, data, f).gamma + f.ddf;
        }
}

void ConstraintSystem::gamma_velocity_transpose(const State& state, Data& data, const Eigen::VectorXd& mu,
                                                Eigen::VectorXd& out) const {
    data.pose(state);
    const Model& m = *model_;
    const int nvb = velocities_per_body(m.dimension);
    Eigen::VectorXd& local = data.joint_gamma_gradient;  // sized for the joint with the most bodies
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = *joint_[j];
        if (!joint.has_gamma_velocity_transpose()) continue;
        if (!flexible_[j]->empty())
            throw DynamicsError(state.t, "joint '" + m.joints[j].name + "' is attached to flexible body '" +
                                             m.flexible_bodies[flexible_[j]->front().body].name +
                                             "', and the derivative of its gamma by the velocities through the "
                                             "material frame is not available: use the augmented formulation with an "
                                             "explicit integrator (dopri5, dop853, rk4)");
        const BodyList bodies = joint_bodies_[j];
        local.head(nvb * bodies.size()).setZero();
        data.poses.fill(bodies, state.t, data.view);
        joint.gamma_velocity_transpose(data.view, mu.data() + joint_offset_[j], local.data());
        for (int b = 0; b < bodies.size(); ++b)
            if (bodies[b] != kGround) out.segment(m.v_offset(bodies[b]), nvb) += local.segment(nvb * b, nvb);
    }
}

const ConstraintEval& ConstraintSystem::evaluate_joint(size_t j, const State& state, Data& data) const {
    ConstraintEval& e = data.joint_rows[j];
    e.C.setZero();
    e.J.setZero();
    e.C_t.setZero();
    e.gamma.setZero();
    const std::vector<FlexibleAttachment>& flexible = *flexible_[j];
    // a joint along a flexible body's curve writes its block over the body itself (curve_joint.hpp)
    const auto* along_curve = flexible.empty() ? nullptr : dynamic_cast<const CurveJoint*>(joint_[j]);
    if (flexible.empty() || along_curve)
        data.poses.fill(joint_bodies_[j], state.t, data.view);
    else
        fill_joint_view(joint_bodies_[j], flexible, data.joint_flexible[j], state.t, data);
    try {
        if (along_curve)
            return evaluate_along_curve(*model_, *along_curve, flexible.front(), data, data.joint_flexible[j].front(), e);
        joint_[j]->evaluate(data.view, e);
    } catch (const DomainError& outside) {
        // the plugin says where its geometry ended; the run stops here, naming the joint and the time
        const JointInstance& ji = model_->joints[j];
        throw DynamicsError(state.t, "joint '" + ji.name + "' (type " + ji.type +
                                         (ji.where.empty() ? "" : ", " + ji.where) + ") left its domain at t = " +
                                         format_time(state.t) + ": " + outside.what());
    }
    if (!flexible.empty()) map_flexible_slots(flexible, data.joint_flexible[j], e.J, e.gamma);
    return e;
}

void ConstraintSystem::fill_joint_view(BodyList bodies, const std::vector<FlexibleAttachment>& flexible,
                                       std::vector<Data::FlexibleSlot>& slots, double t, Data& data) {
    if (flexible.empty())
        data.poses.fill(bodies, t, data.view);
    else
        data.fill_view(bodies, flexible, slots, t);
}

void ConstraintSystem::map_flexible_slots(const std::vector<FlexibleAttachment>& flexible,
                                          std::vector<Data::FlexibleSlot>& slots,
                                          const Eigen::Ref<const Eigen::MatrixXd>& J,
                                          Eigen::Ref<Eigen::VectorXd> gamma) const {
    // the chain rule onto each flexible slot: J = J_f G, gamma -= J_f a (sdk body.hpp); the slot
    // holds the ground, so the rigid scatter skips its block J_f
    const int nvb = velocities_per_body(model_->dimension);
    for (size_t a = 0; a < flexible.size(); ++a)
        map_frame_rows(J.middleCols(nvb * flexible[a].slot, nvb), slots[a].frame, slots[a].J, gamma);
}

bool ConstraintSystem::material_frame(size_t j, int slot, const State& state, Data& data, Mat3& A, Vec3& R,
                                      Eigen::MatrixXd& J_frame) const {
    const std::vector<FlexibleAttachment>& flexible = *flexible_[j];
    const auto* along_curve = flexible.empty() ? nullptr : dynamic_cast<const CurveJoint*>(joint_[j]);
    if (along_curve) {  // the frame at the curve's point where the joint acts, R shifted so that R + A u_bar is it
        if (slot != CurveJoint::kCurveSlot) return false;
        data.pose(state);
        data.poses.fill(joint_bodies_[j], state.t, data.view);
        const int body = flexible.front().body;
        along_curve->curve_frame(data.view, dynamic_cast<const BodyCurve&>(*model_->flexible_bodies[body].body),
                                 data.flexible_q[body], data.flexible_v[body], A, R, J_frame);
        Vec3 u_bar = model_->joints[j].markers[slot].u_bar;
        if (model_->dimension == Dimension::Planar) u_bar.z() = 0.0;
        R -= A * u_bar;
        return true;
    }
    for (size_t a = 0; a < flexible.size(); ++a) {
        if (flexible[a].slot != slot) continue;
        data.pose(state);
        const ConstraintEval& e = evaluate_joint(j, state, data);
        const int nvb = velocities_per_body(model_->dimension);
        J_frame = e.J.middleCols(nvb * slot, nvb);  // evaluate_joint leaves the frame's block in place
        frame_pose(data.joint_flexible[j][a].frame, A, R);
        return true;
    }
    return false;
}

bool ConstraintSystem::driver_material_frame(size_t d, int slot, const State& state, Data& data, Mat3& A, Vec3& R,
                                             Eigen::MatrixXd& J_frame) const {
    const std::vector<FlexibleAttachment>& flexible = *flexible_[model_->drivers[d].joint];
    for (size_t a = 0; a < flexible.size(); ++a) {
        if (flexible[a].slot != slot) continue;
        data.pose(state);
        TimeValue f;
        const CoordinateEval& e = evaluate_driver(d, state, data, f);
        const int nvb = velocities_per_body(model_->dimension);
        // one row (evaluate_driver leaves the frame's block in place)
        J_frame = Eigen::Map<const Eigen::MatrixXd>(e.J.data(), 1, e.J.size()).middleCols(nvb * slot, nvb);
        frame_pose(data.driver_flexible[d][a].frame, A, R);
        return true;
    }
    return false;
}

void ConstraintSystem::frame_pose(const MaterialFrame& frame, Mat3& A, Vec3& R) const {
    A.setIdentity();
    R.setZero();
    if (model_->dimension == Dimension::Planar) {
        A.topLeftCorner<2, 2>() = frame.planar.A;
        R.head<2>() = frame.planar.R;
    } else {
        A = frame.spatial.A;
        R = frame.spatial.R;
    }
}

void ConstraintSystem::throw_if_state_finite(size_t j, const ConstraintEval& e, const State& state) const {
    if (!state.q.allFinite() || !state.v.allFinite()) return;
    // a driver whose motion has grown out of range is the cause (the recursive formulations put
    // it into the joint coordinates directly, and its rates reach every joint beyond it)
    for (const Driver& driver : model_->drivers) require_usable_motion(driver, driver.motion->evaluate(state.t), state.t);
    const JointInstance& ji = model_->joints[j];
    throw DynamicsError(state.t, "joint '" + ji.name + "' (type " + ji.type + (ji.where.empty() ? "" : ", " + ji.where) +
                                     ") gave a non-finite value at t = " + format_time(state.t) + " (" +
                                     first_non_finite(*ji.joint, e) +
                                     ") although the body positions and velocities are finite: its equations "
                                     "are undefined in this configuration; check the joint's parameters, or "
                                     "its plugin");
}

const CoordinateEval& ConstraintSystem::evaluate_driver(size_t d, const State& state, Data& data, TimeValue& f) const {
    const Driver& dr = model_->drivers[d];
    CoordinateEval& e = data.driver_rows[d];
    e.J.setZero();
    e.gamma = 0.0;
    const std::vector<FlexibleAttachment>& flexible = *flexible_[dr.joint];
    if (flexible.empty())
        data.poses.fill(joint_bodies_[dr.joint], state.t, data.view);
    else
        fill_joint_view(joint_bodies_[dr.joint], flexible, data.driver_flexible[d], state.t, data);
    joint_[dr.joint]->coordinate(data.view, e);
    if (!flexible.empty())  // the coordinate's row by the same chain rule as the joint's rows (one row)
        map_flexible_slots(flexible, data.driver_flexible[d], Eigen::Map<const Eigen::MatrixXd>(e.J.data(), 1, e.J.size()),
                           Eigen::Map<Eigen::VectorXd>(&e.gamma, 1));
    f = dr.motion->evaluate(state.t);
    require_usable_motion(dr, f, state.t);
    return e;
}

}  // namespace mbd
