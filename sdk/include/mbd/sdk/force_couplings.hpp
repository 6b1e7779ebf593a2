// Sparse force Jacobians for an element over many bodies (docs/plugin-sdk.md "Sparse force
// Jacobians").
//
// An element that spans many bodies but couples them only two at a time (the collision element
// spans every body with shapes; each of its contacts loads two) implements ForceCouplings beside
// Force. The core then takes the element's Jacobians one coupling at a time, by central
// differences over that coupling's two bodies only, and assembles them as sparse blocks: memory
// and cost grow with the couplings, not with the square of the element's velocities. Without it
// the core differences the whole element over each of its velocities in an n x n workspace.
//
// The core finds the interface by dynamic_cast from the element's Force, so an element that
// does not implement it is unchanged.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>

#include <Eigen/Core>

#include <vector>

namespace mbd {

// One coupling: the part of the element's force that depends on two of its bodies only.
struct ForceCoupling {
    int body_i = 0, body_j = 0;  // positions in the element's body list (ForceSpec::bodies), different
    int item_i = 0, item_j = 0;  // the element's own labels for it (the collision element: two shapes)
};

class MBD_SDK_API ForceCouplings {
public:
    virtual ~ForceCouplings() = default;

    // The couplings at these bodies' states, written into `out` (cleared first). The element's Q
    // (Force::evaluate) must be exactly the sum of their coupling_force at these states, and
    // stay so under small changes of the two bodies of each (no coupling appears or vanishes
    // within the differencing step, except where the force itself is not differentiable).
    virtual void couplings(const BodyStates& bodies, std::vector<ForceCoupling>& out) const = 0;

    // Coupling c's force: 2 * velocities_per_body entries, body_i's block then body_j's, added
    // into Q, computed from the states of c.body_i and c.body_j in `bodies` only.
    virtual void coupling_force(const BodyStates& bodies, const ForceCoupling& c,
                                Eigen::Ref<Eigen::VectorXd> Q) const = 0;
};

}  // namespace mbd
