// The body states a force element sees, built from a spatial scene's State, for tests that
// evaluate an element directly (its generalized forces, its potential energy).
#pragma once

#include <mbd/model.hpp>
#include <mbd/sdk/body_state.hpp>
#include <mbd/kit/state.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace mbd::test {

// The spatial states of every body of a force element (ground first when it has shapes).
struct ElementStates {
    std::vector<mbd::SpatialBody> bodies;
    mbd::BodyStates view;
    ElementStates(const mbd::ForceInstance& f, const mbd::State& s) {
        bodies.resize(f.bodies.size());
        for (size_t k = 0; k < f.bodies.size(); ++k) {
            const int b = f.bodies[k];
            if (b < 0) {
                bodies[k].ground = true;
                continue;
            }
            bodies[k].set(s.q.segment<3>(7 * b), s.q.segment<4>(7 * b + 3), s.v.segment<3>(6 * b),
                          s.v.segment<3>(6 * b + 3));
        }
        for (const auto& b : bodies) view.spatial_bodies.push_back(&b);
    }
};

inline const mbd::ForceInstance& element(const mbd::Model& model, const std::string& type) {
    for (const auto& f : model.forces)
        if (f.type == type) return f;
    throw std::runtime_error("no force of type " + type);
}

}  // namespace mbd::test
