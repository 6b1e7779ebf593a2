// Event-located impacts between collision shapes (docs/scene-format.md "Impacts"): the pairs of
// shapes whose material asks for Newton's law (`impact:`, collision_material.hpp) are rigid at
// touch-down. Each such pair is one event of the collision element (mbd/sdk/force.hpp "Events"):
// its gap g (signed distance, >= 0 while apart) and the gradient G = dg/dv along which the core
// applies the impulse on the constrained system (core contact_events.hpp: the mass matrix and
// the joints' Jacobian, so a jointed body or a second free body takes its share of the impulse).
//
// The gap of a pair, with n the unit normal from shape a toward shape b and X the contact point:
//  - sphere b on plane a:  g = n . (C_b - P_a) - r_b, n the plane's normal, X = C_b - r_b n;
//  - spheres a and b:      g = |C_b - C_a| - r_a - r_b, n along the line of centres, X the middle
//    of the gap on that line.
// Its rate is gdot = n . (v_b(X) - v_a(X)) (the normal does not turn the rate: n . (w x n) = 0),
// so G holds +-n on each body's translation and +-A^T ((X - R) x n) on its rotation (body axes,
// as the generalized forces). These two pairs have exact gaps; the others (boxes, capsules,
// cylinders, meshes) are refused by name when a material of theirs asks for impacts.
#pragma once

#include "collision_world.hpp"

#include <mbd/sdk/force.hpp>

#include <string>
#include <vector>

namespace mbd::collision {

class ImpactPairs {
public:
    ImpactPairs() = default;
    // Every pair of `shapes` that may touch (`filter`) and whose materials ask for impacts.
    ImpactPairs(const std::vector<Shape>& shapes, const PairFilter& filter);

    int count() const { return static_cast<int>(pairs_.size()); }
    std::string name(int pair) const;
    void values(const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> g) const;
    EventImpact impact(int pair, const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> G) const;

private:
    struct Pair {
        int a, b;  // shape indices; a is the plane of a sphere-plane pair
        double restitution, rest_velocity;
    };
    struct Gap {
        double gap;
        Vec3 normal, point;  // from shape a toward shape b; world
    };
    Gap gap(const Pair& p, const BodyStates& bodies) const;

    const std::vector<Shape>* shapes_ = nullptr;
    std::vector<Pair> pairs_;
};

}  // namespace mbd::collision
