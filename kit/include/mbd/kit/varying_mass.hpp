// Flexible bodies whose mass matrix varies with their coordinates (the floating frame,
// ffrf_body: M(q) couples the frame's rotation and the modes; sdk body.hpp constant_mass()).
// A System that has them also implements this interface; a formulation that takes them finds
// it by varying_mass(system) and, before each use of mass_matrix() at a state, re-evaluates
// those blocks at the state's positions (the constant blocks, rigid bodies and ANCF, stay as
// bound). Kept apart from System so that a scene without such a body changes nothing.
#pragma once

#include <mbd/kit/system.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mbd {

class VaryingMass {
public:
    virtual ~VaryingMass() = default;
    // A body's velocity range in v (its diagonal block of the mass matrix) and its name.
    struct Block {
        int offset = 0;
        int size = 0;
        std::string name;
    };
    // The blocks that vary, in v order; empty: none (every block constant).
    virtual const std::vector<Block>& varying_mass_blocks() const = 0;
    // Re-evaluates those blocks of mass_matrix() at positions q (nq); the others are unchanged.
    virtual void update_mass_matrix(const Eigen::VectorXd& q) = 0;
};

// The system's varying blocks, or null when it has none.
inline VaryingMass* varying_mass(System& system) {
    auto* v = dynamic_cast<VaryingMass*>(&system);
    return v && !v->varying_mass_blocks().empty() ? v : nullptr;
}

}  // namespace mbd
