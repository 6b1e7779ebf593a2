// Per-body pose cache: rotation matrices evaluated once per state, shared by
// every joint and force that touches the body.
#pragma once

#include <mbd/element_bodies.hpp>
#include <mbd/model.hpp>

namespace mbd {

class BodyPoses {
public:
    explicit BodyPoses(const Model& model);

    void update(const State& state);
    // the velocities only, the positions (and so the rotation matrices) being those of the last update()
    void update_velocities(const State& state);

    // The view an element with these body indices evaluates on.
    BodyStates view(const std::vector<int>& bodies, double t) const;
    void fill(const std::vector<int>& bodies, double t, BodyStates& out) const;
    void fill(BodyList bodies, double t, BodyStates& out) const;

    const PlanarBody& planar(int body) const { return body == kGround ? planar_ground_ : planar_[body]; }
    const SpatialBody& spatial(int body) const { return body == kGround ? spatial_ground_ : spatial_[body]; }

private:
    const Model* model_;
    std::vector<PlanarBody> planar_;
    std::vector<SpatialBody> spatial_;
    PlanarBody planar_ground_;
    SpatialBody spatial_ground_;
};

}  // namespace mbd
