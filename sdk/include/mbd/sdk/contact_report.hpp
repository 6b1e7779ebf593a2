// The contacts a force element holds at a state, for output (docs/plugin-sdk.md "Reporting
// contacts"): `mbd simulate --contacts` writes them, one row per contact, and the viewer draws
// them. A force plugin that finds contacts itself (the collision element) implements this
// interface beside Force; the core asks each force element for it (a cross-cast from Force), so
// an element that does not report contacts needs nothing and the Force interface is unchanged.
#pragma once

#include <mbd/sdk/body_state.hpp>

#include <vector>

namespace mbd {

// One active contact between two of the element's bodies. Its force acts at `point` on body_j
// (normal_force n + friction_force) and its opposite on body_i.
struct ContactReport {
    int body_i = 0, body_j = 0;    // positions in the element's body list (ForceSpec::bodies)
    Vec3 point = Vec3::Zero();     // world
    Vec3 normal = Vec3::Zero();    // unit, world, from body i toward body j
    double depth = 0.0;            // penetration, > 0
    double normal_force = 0.0;     // along `normal`, on body j (> 0 pushes the bodies apart)
    Vec3 friction_force = Vec3::Zero();  // tangential (normal . friction_force = 0), on body j
    Vec3 rolling_torque = Vec3::Zero();  // the rolling resistance's torque on body j, world (zero without)
};

class MBD_SDK_API ContactReporter {
public:
    virtual ~ContactReporter() = default;
    // Every contact with a force at these body states, the forces exactly those evaluate() adds.
    virtual std::vector<ContactReport> contacts(const BodyStates& bodies) const = 0;
};

}  // namespace mbd
