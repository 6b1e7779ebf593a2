// The file of a mesh a model file names (URDF <mesh filename>, SDF <mesh><uri>), as mbd's
// viewer can draw it (docs/import.md): a missing or undrawable mesh is listed, never an error.
#pragma once

#include <string>

namespace mbd::import {

enum class MeshLookup { Found, Missing, Undrawable };

// `uri` without its package://, model:// or file:// scheme, relative paths from the folder of
// `model_file`. Found: `path` is the absolute path of an STL, OBJ, DAE (Collada) or glTF file;
// Undrawable: a file of another kind (mbd's viewer draws those four); Missing: no such file.
MeshLookup find_mesh(const std::string& uri, const std::string& model_file, std::string& path);

}  // namespace mbd::import
