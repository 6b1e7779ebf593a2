// An MJCF (or URDF) file compiled by MuJoCo's own compiler (mj_loadXML) when some of the mesh or
// texture files it names are missing (docs/import.md, "Missing mesh files"): each file MuJoCo
// cannot open is supplied as a placeholder through MuJoCo's virtual file system (mjVFS: a small
// tetrahedron for a mesh, one pixel for a texture), and the file is compiled twice, with the
// placeholder at two sizes. A body whose mass, mass centre or inertia differs between the two takes
// its inertia from a missing mesh (inertiafromgeom): the file is refused. The user's file is never
// written or copied. Depends on MuJoCo and the standard library only, so that the import, the
// tests' MuJoCo oracle and the MuJoCo bench peer share it.
#pragma once

#include <mujoco/mujoco.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace mbd::import {

// A file MuJoCo could not open, as its compiler looked for it, with the asset that names it.
struct MissingAsset {
    std::string path;    // the full path MuJoCo tried
    std::string kind;    // "mesh" or "texture"
    std::string object;  // the asset's name in MuJoCo's message (a mesh without one: its file's stem)
    std::string line;    // the asset's XML line
};

struct MjcfCompilation {
    std::unique_ptr<mjModel, void (*)(mjModel*)> model{nullptr, mj_deleteModel};
    std::vector<MissingAsset> missing;  // placeholders supplied, in the order MuJoCo asked for them
    std::vector<int> placeholder_geoms; // geoms whose size or pose comes from a placeholder
    std::string error;                  // why `model` is null: MuJoCo's message (one line) or the check's
    bool inertia_from_missing_mesh = false;  // the check refused it (then `error` names the body)
};

// `file` compiled with placeholders for its missing mesh and texture files (above). On failure the
// model is null and `error` says why; a body whose inertia comes from a missing mesh is named there.
MjcfCompilation compile_mjcf(const std::filesystem::path& file);

// For a warning: each missing file with the asset that names it and the geoms drawn from it
// ("/m/assets/link0.stl (mesh 'link0_c', line 47: geom #3 of body 'link0')"), and in `others` the
// placeholder geoms not listed so: those of a mesh reusing a file MuJoCo asked for already (it names
// the first asset only), and primitives fitted to a missing mesh.
std::vector<std::string> describe_missing(const MjcfCompilation& compiled, std::vector<std::string>& others);

}  // namespace mbd::import
