// A mode file: the nodes of a body (undeformed position in body axes and a lumped mass) and its
// modes (modal mass, modal stiffness, and each node's displacement and small rotation), as text:
//
//     # comments and blank lines are skipped
//     nodes 3                      # the number of nodes
//     0.0 0.0 0.5                  # x y mass, one line per node
//     ...
//     mode 1.0 12.36               # modal mass, modal stiffness
//     0.0 0.0 0.0                  # ux uy rotation, one line per node
//     ...                          # (as many modes as wanted)
//
// The inertia integrals (modal_model.hpp) are sums over the lumped masses, except Mff, which is
// diag(modal masses) as the file gives it (modes orthogonal in the mass).
#pragma once

#include "modal_model.hpp"

#include <string>

namespace mbd::ffrf {

// Throws InputError naming `owner` (the body): at the mode file's file:line for a malformed file,
// at `where` (the scene's file:line of the key that names it) for a file that cannot be opened.
ModalModel read_mode_file(const std::string& path, const std::string& owner, const std::string& where);

}  // namespace mbd::ffrf
