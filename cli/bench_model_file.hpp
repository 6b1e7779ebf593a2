// `mbd bench MODEL_FILE` (docs/benchmarks.md, "Model files"): a URDF or MJCF file benchmarked
// with a default spec, run by mbd (imported) and by every peer that reads the file itself
// (MuJoCo: MJCF and URDF; DART: URDF), all from the same file.
#pragma once

#include <mbd/app/bench.hpp>

#include <filesystem>

namespace mbd {

struct ModelFileBench {
    Model model;     // the imported model, in its documented initial state
    BenchSpec spec;  // the default spec
};

// The documented initial state: hinge or slide joint number k (the file's order, from 0) turns
// or slides at (-1)^k (1 + 0.1 k) rad/s or m/s; a free joint's body moves at (0.3, -0.2, 1.0) m/s
// and turns at (0.5, -0.4, 0.8) rad/s in its body axes; other joints start at rest. Positions
// are the file's reference configuration.
// The default spec: 1 s, output every 0.01 s; measured: the mass centre of every body that is
// one body of the file (not a frame body between two joints of one source body, nor a body
// into which other bodies with mass were merged); reference: a tight run (embedding + dop853 at
// tol 1e-12, cross-checked by augmented); mbd: the automatic formulation with dopri5 (tol 1e-3
// to 1e-11) and dop853 (1e-4 to 1e-12); MuJoCo RK4 at steps 1e-2 to 1e-5 (MJCF and URDF); DART's
// semi-implicit Euler at steps 1e-2 to 1e-5 (URDF).
// InputError (naming the file) when the file cannot be imported.
ModelFileBench model_file_bench(const std::filesystem::path& file, Registry& registry);

}  // namespace mbd
