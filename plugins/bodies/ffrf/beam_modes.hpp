// The modes of a cantilever computed from a mesh of Euler-Bernoulli beam elements (cubic Hermite,
// shared/hermite.hpp), clamped at the FFRF body's frame origin and lying along its x axis: the
// frame is the tangent frame at the root, so the modes are the cantilever's (transverse, in the
// plane of the body), mass-normalized: Mff = I, Kff = diag(omega_i^2) (to round-off: Kff is
// integrated from the modes' curvatures, beam_modes.cpp).
#pragma once

#include "modal_model.hpp"

namespace mbd::ffrf {

struct BeamSection {
    double EI = 0.0;    // bending stiffness
    double rhoA = 0.0;  // mass per unit length
};

// The lowest `modes` modes of a cantilever of `length` meshed into `elements` elements
// (modes <= 2 elements, the mesh's free coordinates), with Kg for geometric stiffening.
ModalModel cantilever_modes(double length, int elements, int modes, const BeamSection& section);

}  // namespace mbd::ffrf
