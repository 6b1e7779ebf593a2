#include "evaluation/coupled_force_jacobians.hpp"

#include <mbd/sdk/rotation.hpp>

#include <Eigen/Dense>

namespace mbd {

const ForceCouplings* force_couplings(const ForceInstance& f) {
    return dynamic_cast<const ForceCouplings*>(f.force.get());
}

namespace {

constexpr double kStep = 1e-7;  // ModelSystem::force_differences' step

// The state of model body k with its velocity `column` (-1: none) moved by `step`, in the
// positions (the increment of advance_positions, applied to every body of the coupling as
// advance_positions applies it to every body) or in the velocities: the same arithmetic as
// advance_positions followed by BodyPoses::update, so the numbers equal the whole element's.
void perturbed(const Model& m, const State& s, int k, int column, double step, bool velocity, PlanarBody& out) {
    const int iq = m.q_offset(k), iv = m.v_offset(k);
    Eigen::Vector3d q = s.q.segment<3>(iq), v = s.v.segment<3>(iv);
    if (column >= 0) (velocity ? v : q)[column] += step;
    out.set(q.head<2>(), q[2], v.head<2>(), v[2]);
}

void perturbed(const Model& m, const State& s, int k, int column, double step, bool velocity, SpatialBody& out) {
    const int iq = m.q_offset(k), iv = m.v_offset(k);
    Vec3 R = s.q.segment<3>(iq), Rdot = s.v.segment<3>(iv), w = s.v.segment<3>(iv + 3);
    Vec4 p = s.q.segment<4>(iq + 3);
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    if (column >= 0) d[column] = step;
    if (velocity) {
        Rdot += d.head<3>();
        w += d.tail<3>();
    } else {
        R += d.head<3>();
        p = rotate_euler_parameters_body(p, d.tail<3>());
    }
    out.set(R, p, Rdot, w);
}

// One coupling's Jacobian blocks by central differences; Body is PlanarBody or SpatialBody.
template <class Body>
class CouplingDifferences {
public:
    CouplingDifferences(const Model& m, const ForceInstance& f, const ForceCouplings& element, const State& s,
                        BodyStates& view)
        : m_(m), f_(f), element_(element), s_(s), view_(view), nvb_(velocities_per_body(m.dimension)),
          plus_(2 * nvb_), minus_(2 * nvb_), dq_(2 * nvb_, 2 * nvb_), dv_(2 * nvb_, 2 * nvb_) {}

    void add(const ForceCoupling& c, std::vector<Eigen::Triplet<double>>& tq, std::vector<Eigen::Triplet<double>>& tv) {
        const int ends[2] = {c.body_i, c.body_j};
        dq_.setZero();
        dv_.setZero();
        for (int e = 0; e < 2; ++e) {
            if (f_.bodies[ends[e]] == kGround) continue;
            for (int col = 0; col < nvb_; ++col)
                for (bool velocity : {false, true}) {
                    evaluate(c, ends, e, col, kStep, velocity, plus_);
                    evaluate(c, ends, e, col, -kStep, velocity, minus_);
                    (velocity ? dv_ : dq_).col(nvb_ * e + col) = (plus_ - minus_) / (2 * kStep);
                }
        }
        scatter(ends, dq_, tq);
        scatter(ends, dv_, tv);
    }

private:
    // coupling c's force with velocity `col` of end e moved by `step`, every other state as is
    void evaluate(const ForceCoupling& c, const int ends[2], int e, int col, double step, bool velocity,
                  Eigen::VectorXd& Q) {
        auto& slots = slots_of(view_);
        const Body* saved[2] = {slots[ends[0]], slots[ends[1]]};
        for (int k = 0; k < 2; ++k) {
            const int body = f_.bodies[ends[k]];
            if (body == kGround) continue;
            // the other end moves by a zero increment, as in advance_positions
            perturbed(m_, s_, body, k == e ? col : -1, step, velocity, probes_[k]);
            slots[ends[k]] = &probes_[k];
        }
        Q.setZero();
        element_.coupling_force(view_, c, Q);
        slots[ends[0]] = saved[0];
        slots[ends[1]] = saved[1];
    }

    void scatter(const int ends[2], const Eigen::MatrixXd& local, std::vector<Eigen::Triplet<double>>& out) const {
        for (int a = 0; a < 2; ++a) {
            if (f_.bodies[ends[a]] == kGround) continue;
            for (int b = 0; b < 2; ++b) {
                if (f_.bodies[ends[b]] == kGround) continue;
                const int row = m_.v_offset(f_.bodies[ends[a]]), column = m_.v_offset(f_.bodies[ends[b]]);
                for (int i = 0; i < nvb_; ++i)
                    for (int j = 0; j < nvb_; ++j) {
                        const double value = local(nvb_ * a + i, nvb_ * b + j);
                        if (value != 0.0) out.emplace_back(row + i, column + j, value);
                    }
            }
        }
    }

    static std::vector<const PlanarBody*>& slots_of_impl(BodyStates& v, const PlanarBody*) { return v.planar_bodies; }
    static std::vector<const SpatialBody*>& slots_of_impl(BodyStates& v, const SpatialBody*) { return v.spatial_bodies; }
    static auto& slots_of(BodyStates& v) { return slots_of_impl(v, static_cast<const Body*>(nullptr)); }

    const Model& m_;
    const ForceInstance& f_;
    const ForceCouplings& element_;
    const State& s_;
    BodyStates& view_;
    const int nvb_;
    Eigen::VectorXd plus_, minus_;
    Eigen::MatrixXd dq_, dv_;
    Body probes_[2];
};

template <class Body>
void add_all(const Model& m, const ForceInstance& f, const ForceCouplings& element, const State& state,
             BodyStates& view, const std::vector<ForceCoupling>& couplings, std::vector<Eigen::Triplet<double>>& tq,
             std::vector<Eigen::Triplet<double>>& tv) {
    CouplingDifferences<Body> differences(m, f, element, state, view);
    for (const ForceCoupling& c : couplings) differences.add(c, tq, tv);
}

}  // namespace

void add_coupled_force_jacobians(const Model& m, const ForceInstance& f, const ForceCouplings& element,
                                 const State& state, const BodyPoses& poses, BodyStates& view,
                                 std::vector<Eigen::Triplet<double>>& dQ_dq,
                                 std::vector<Eigen::Triplet<double>>& dQ_dv) {
    poses.fill(f.bodies, state.t, view);
    std::vector<ForceCoupling> couplings;
    element.couplings(view, couplings);
    if (m.dimension == Dimension::Planar)
        add_all<PlanarBody>(m, f, element, state, view, couplings, dQ_dq, dQ_dv);
    else
        add_all<SpatialBody>(m, f, element, state, view, couplings, dQ_dq, dQ_dv);
}

}  // namespace mbd
