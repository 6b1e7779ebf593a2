#include <mbd/body_poses.hpp>

namespace mbd {

BodyPoses::BodyPoses(const Model& model) : model_(&model) {
    if (model.dimension == Dimension::Planar) {
        planar_.resize(model.body_count());
        planar_ground_.ground = true;
    } else {
        spatial_.resize(model.body_count());
        spatial_ground_.ground = true;
    }
}

void BodyPoses::update(const State& state) {
    const Model& m = *model_;
    for (int k = 0; k < m.body_count(); ++k) {
        const int iq = m.q_offset(k), iv = m.v_offset(k);
        if (m.dimension == Dimension::Planar) {
            planar_[k].set(state.q.segment<2>(iq), state.q[iq + 2], state.v.segment<2>(iv), state.v[iv + 2]);
        } else {
            spatial_[k].set(state.q.segment<3>(iq), state.q.segment<4>(iq + 3), state.v.segment<3>(iv),
                            state.v.segment<3>(iv + 3));
        }
    }
}

void BodyPoses::update_velocities(const State& state) {
    const Model& m = *model_;
    for (int k = 0; k < m.body_count(); ++k) {
        const int iv = m.v_offset(k);
        if (m.dimension == Dimension::Planar) {
            planar_[k].Rdot = state.v.segment<2>(iv);
            planar_[k].omega = state.v[iv + 2];
        } else {
            spatial_[k].Rdot = state.v.segment<3>(iv);
            spatial_[k].omega_bar = state.v.segment<3>(iv + 3);
        }
    }
}

void BodyPoses::fill(const std::vector<int>& bodies, double t, BodyStates& out) const {
    fill(BodyList{bodies.data(), static_cast<int>(bodies.size())}, t, out);
}

void BodyPoses::fill(BodyList bodies, double t, BodyStates& out) const {
    out.t = t;
    out.planar_bodies.clear();
    out.spatial_bodies.clear();
    for (int b : bodies) {
        if (model_->dimension == Dimension::Planar)
            out.planar_bodies.push_back(&planar(b));
        else
            out.spatial_bodies.push_back(&spatial(b));
    }
}

BodyStates BodyPoses::view(const std::vector<int>& bodies, double t) const {
    BodyStates out;
    fill(bodies, t, out);
    return out;
}

}  // namespace mbd
