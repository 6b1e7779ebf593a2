// mesh_file.hpp.
#include <mbd/import/mesh_file.hpp>

#include <cctype>
#include <filesystem>

namespace mbd::import {

MeshLookup find_mesh(const std::string& uri, const std::string& model_file, std::string& path) {
    std::string name = uri;
    for (const char* scheme : {"package://", "model://", "file://"})
        if (name.rfind(scheme, 0) == 0) name = name.substr(std::string(scheme).size());
    std::filesystem::path file(name);
    if (file.is_relative()) file = std::filesystem::absolute(std::filesystem::path(model_file).parent_path() / file);
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) return MeshLookup::Missing;
    std::string ext = file.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    // The formats mbd's viewer reads (core/src/scene/visual.cpp accepts the same in a scene).
    if (ext != ".stl" && ext != ".obj" && ext != ".dae" && ext != ".gltf" && ext != ".glb") return MeshLookup::Undrawable;
    path = file.lexically_normal().string();
    return MeshLookup::Found;
}

}  // namespace mbd::import
