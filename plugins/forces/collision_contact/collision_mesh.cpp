#include "collision_mesh.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>

namespace mbd::collision {

namespace {

std::string resolve(const Param& at, const std::string& file, const std::string& owner) {
    std::filesystem::path path(file);
    if (path.is_relative()) path = std::filesystem::path(at.file).parent_path() / path;
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
        at.fail(owner + ": mesh file '" + path.string() +
                "' not found (an STL or OBJ file; a relative path is relative to the scene file's folder)");
    return path.string();
}

}  // namespace

std::shared_ptr<const Mesh> read_mesh(const Param& at, const std::string& file, const Vec3& scale,
                                      const std::string& owner) {
    const std::string path = resolve(at, file, owner);
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices);
    if (!scene || !scene->mRootNode || scene->mNumMeshes == 0)
        at.fail(owner + ": cannot read the mesh '" + path + "' (" +
                std::string(scene ? "it has no triangles" : importer.GetErrorString()) +
                "); give an STL or OBJ file with triangles");
    auto mesh = std::make_shared<Mesh>();
    // one vertex per position: an STL repeats each corner in every triangle that has it
    std::map<std::tuple<double, double, double>, int> index;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* part = scene->mMeshes[m];
        std::vector<int> merged(part->mNumVertices);
        for (unsigned v = 0; v < part->mNumVertices; ++v) {
            const aiVector3D& p = part->mVertices[v];
            const Vec3 x = Vec3(p.x, p.y, p.z).cwiseProduct(scale);
            if (!x.allFinite())
                at.fail(owner + ": the mesh '" + path + "' has a vertex that is not a finite number; fix the file");
            const auto found = index.try_emplace({x.x(), x.y(), x.z()}, static_cast<int>(mesh->vertices.size()));
            if (found.second) mesh->vertices.push_back(x);
            merged[v] = found.first->second;
        }
        for (unsigned f = 0; f < part->mNumFaces; ++f) {
            const aiFace& face = part->mFaces[f];
            if (face.mNumIndices != 3) continue;  // points and lines of an OBJ
            mesh->triangles.push_back(
                {merged[face.mIndices[0]], merged[face.mIndices[1]], merged[face.mIndices[2]]});
        }
    }
    if (mesh->triangles.empty()) at.fail(owner + ": the mesh '" + path + "' has no triangles");
    return mesh;
}

void check_convex(const Mesh& mesh, const Param& at, const std::string& file, const std::string& owner) {
    // closed: each directed edge once, and its reverse once (a consistently oriented closed surface)
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    for (const auto& [edge, count] : edges) {
        const auto reverse = edges.find({edge.second, edge.first});
        const int back = reverse == edges.end() ? 0 : reverse->second;
        if (count != 1 || back != 1) {
            const Vec3& a = mesh.vertices[edge.first];
            const Vec3& b = mesh.vertices[edge.second];
            at.fail(owner + ": the mesh '" + file + "' is not closed (the edge from (" + format_number(a.x()) + ", " +
                    format_number(a.y()) + ", " + format_number(a.z()) + ") to (" + format_number(b.x()) + ", " +
                    format_number(b.y()) + ", " + format_number(b.z()) + ") belongs to " +
                    std::to_string(count + back) + " triangle(s), not 2, or they disagree on the outside); a "
                    "convex_mesh must be a closed convex surface: close the mesh, or use triangle_mesh on the ground");
        }
    }
    // convex: no vertex in front of a triangle's plane (beyond rounding of the mesh's size)
    double size = 0.0;
    for (const Vec3& v : mesh.vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
    for (const auto& t : mesh.triangles) {
        const Vec3& a = mesh.vertices[t[0]];
        const Vec3 n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
        if (!(n.norm() > 0.0)) continue;  // a degenerate triangle has no plane
        const Vec3 u = n.normalized();
        for (const Vec3& v : mesh.vertices)
            if (u.dot(v - a) > 1e-9 * size)
                at.fail(owner + ": the mesh '" + file + "' is not convex (the vertex (" + format_number(v.x()) + ", " +
                        format_number(v.y()) + ", " + format_number(v.z()) + ") lies " +
                        format_number(u.dot(v - a)) + " m outside the plane of a triangle, or the triangles face "
                        "inward); a convex_mesh must be convex: split the part into convex meshes");
    }
}

}  // namespace mbd::collision
