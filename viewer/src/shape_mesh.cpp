// Tessellation of the visual shapes and reading of mesh files (Assimp).
#include <mbd/viewer/shape_mesh.hpp>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

namespace mbd::viewer {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Builder {
    Tessellation detail;
    TriangleMesh mesh;
    uint32_t vertex(const Vec3& p, const Vec3& n) {
        const Vec3 u = n.normalized();
        for (int k = 0; k < 3; ++k) {
            mesh.positions.push_back(static_cast<float>(p[k]));
            mesh.normals.push_back(static_cast<float>(u[k]));
        }
        return static_cast<uint32_t>(mesh.positions.size() / 3 - 1);
    }
    void triangle(uint32_t a, uint32_t b, uint32_t c) { mesh.indices.insert(mesh.indices.end(), {a, b, c}); }
    void quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {  // counter-clockwise a b c d
        triangle(a, b, c);
        triangle(a, c, d);
    }
};

TriangleMesh box(const Vec3& size) {
    Builder b;
    const Vec3 h = 0.5 * size;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign : {-1, 1}) {
            Vec3 n = Vec3::Zero();
            n[axis] = sign;
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            Vec3 du = Vec3::Zero(), dv = Vec3::Zero();
            du[u] = h[u];
            dv[v] = h[v];
            if (sign < 0) std::swap(du, dv);  // keep the winding counter-clockwise from outside
            const Vec3 c = n.cwiseProduct(h);
            const uint32_t i0 = b.vertex(c - du - dv, n), i1 = b.vertex(c + du - dv, n), i2 = b.vertex(c + du + dv, n),
                           i3 = b.vertex(c - du + dv, n);
            b.quad(i0, i1, i2, i3);
        }
    return b.mesh;
}

// A surface of revolution about z through the profile points (r, z) with outward normals
// (nr, nz); rings of detail.segments vertices joined by quads.
void revolve(Builder& b, const std::vector<std::array<double, 4>>& profile) {
    std::vector<uint32_t> previous;
    for (const auto& [r, z, nr, nz] : profile) {
        std::vector<uint32_t> ring;
        for (int s = 0; s <= b.detail.segments; ++s) {
            const double phi = 2.0 * kPi * s / b.detail.segments;
            const double c = std::cos(phi), si = std::sin(phi);
            ring.push_back(b.vertex(Vec3(r * c, r * si, z), Vec3(nr * c, nr * si, nz)));
        }
        if (!previous.empty())
            for (int s = 0; s < b.detail.segments; ++s) b.quad(previous[s], previous[s + 1], ring[s + 1], ring[s]);
        previous = ring;
    }
}

// Half sphere profiles from the equator (z0) to the pole in direction `sign`.
void hemisphere_profile(std::vector<std::array<double, 4>>& profile, int rings, double radius, double z0, int sign) {
    for (int k = 0; k <= rings / 2; ++k) {
        const double theta = 0.5 * kPi * k / (rings / 2);  // 0 at the equator
        const double nr = std::cos(theta), nz = sign * std::sin(theta);
        profile.push_back({radius * nr, z0 + radius * nz, nr, nz});
    }
}

void disk(Builder& b, double radius, double z, int sign) {
    const Vec3 n(0, 0, sign);
    const uint32_t centre = b.vertex(Vec3(0, 0, z), n);
    std::vector<uint32_t> ring;
    for (int s = 0; s <= b.detail.segments; ++s) {
        const double phi = 2.0 * kPi * s / b.detail.segments;
        ring.push_back(b.vertex(Vec3(radius * std::cos(phi), radius * std::sin(phi), z), n));
    }
    for (int s = 0; s < b.detail.segments; ++s)
        if (sign > 0)
            b.triangle(centre, ring[s], ring[s + 1]);
        else
            b.triangle(centre, ring[s + 1], ring[s]);
}

TriangleMesh sphere(double radius, Tessellation detail) {
    Builder b{detail};
    std::vector<std::array<double, 4>> profile;
    for (int k = 0; k <= detail.rings; ++k) {
        const double theta = kPi * k / detail.rings - 0.5 * kPi;  // south pole to north pole
        profile.push_back({radius * std::cos(theta), radius * std::sin(theta), std::cos(theta), std::sin(theta)});
    }
    revolve(b, profile);
    return b.mesh;
}

TriangleMesh cylinder(double radius, double z0, double z1, Tessellation detail) {
    Builder b{detail};
    revolve(b, {{radius, z0, 1, 0}, {radius, z1, 1, 0}});
    disk(b, radius, z0, -1);
    disk(b, radius, z1, 1);
    return b.mesh;
}

TriangleMesh capsule(double radius, double length, Tessellation detail) {
    Builder b{detail};
    std::vector<std::array<double, 4>> profile;
    std::vector<std::array<double, 4>> bottom;
    hemisphere_profile(bottom, detail.rings, radius, -0.5 * length, -1);
    profile.assign(bottom.rbegin(), bottom.rend());  // south pole up to the lower equator
    hemisphere_profile(profile, detail.rings, radius, 0.5 * length, 1);
    revolve(b, profile);
    return b.mesh;
}

TriangleMesh mesh_file(const VisualShape& shape) {
    Assimp::Importer importer;
    // A Collada file is drawn in its own axes, scaled to metres by its <unit meter>, as ROS's rviz
    // and Gazebo draw a robot's DAE meshes: Assimp would also turn a Z_UP file to y up, which
    // would lay every ROS mesh on its side. glTF (metres, no up-axis conversion by Assimp) and
    // STL/OBJ are drawn as written.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    const aiScene* scene = importer.ReadFile(shape.mesh_file, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                                  aiProcess_GenSmoothNormals |
                                                                  aiProcess_PreTransformVertices);
    if (!scene || !scene->mRootNode || scene->mNumMeshes == 0)
        throw InputError(shape.where, "key 'file': cannot read the mesh " + shape.mesh_file + " (" +
                                          std::string(scene ? "it has no triangles" : importer.GetErrorString()) +
                                          "); give an STL, OBJ, DAE or glTF file with triangles");
    Builder b;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* mesh = scene->mMeshes[m];
        if (!mesh->HasNormals()) continue;
        const uint32_t base = static_cast<uint32_t>(b.mesh.positions.size() / 3);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
                throw InputError(shape.where, "key 'file': the mesh " + shape.mesh_file + " has a vertex that is not a "
                                              "finite number (vertex " + std::to_string(v + 1) + " of part " +
                                              std::to_string(m + 1) + ": " + std::to_string(p.x) + ", " +
                                              std::to_string(p.y) + ", " + std::to_string(p.z) + "); fix the file");
            aiVector3D n = mesh->mNormals[v];
            if (!(n.Length() > 0)) n = aiVector3D(0, 0, 1);
            b.vertex(Vec3(p.x, p.y, p.z), Vec3(n.x, n.y, n.z));
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices == 3)
                b.triangle(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
        }
    }
    if (b.mesh.indices.empty())
        throw InputError(shape.where, "key 'file': the mesh " + shape.mesh_file + " has no triangles");
    return b.mesh;
}

}  // namespace

void TriangleMesh::update_bounds() {
    for (int k = 0; k < 3; ++k) {
        min[k] = positions.empty() ? 0.0f : positions[k];
        max[k] = min[k];
    }
    for (size_t i = 0; i < positions.size(); ++i) {
        min[i % 3] = std::min(min[i % 3], positions[i]);
        max[i % 3] = std::max(max[i % 3], positions[i]);
    }
}

Tessellation tessellation_for(size_t shapes) {
    if (shapes <= 200) return {32, 16};
    if (shapes <= 1000) return {16, 8};
    return {12, 6};
}

TriangleMesh shape_mesh(const VisualShape& shape, Tessellation detail) {
    TriangleMesh mesh;
    switch (shape.kind) {
        case ShapeKind::Box: mesh = box(shape.size); break;
        case ShapeKind::Sphere: mesh = sphere(shape.radius, detail); break;
        case ShapeKind::Cylinder: mesh = cylinder(shape.radius, -0.5 * shape.length, 0.5 * shape.length, detail); break;
        case ShapeKind::Capsule: mesh = capsule(shape.radius, shape.length, detail); break;
        case ShapeKind::Mesh: mesh = mesh_file(shape); break;
    }
    mesh.update_bounds();
    return mesh;
}

SceneMeshes scene_meshes(const VisualScene& scene) {
    SceneMeshes out;
    size_t shapes = scene.ground.size() + scene.connectors.size();
    for (const auto& body : scene.bodies) shapes += body.size();
    const Tessellation detail = tessellation_for(shapes);
    // each distinct shape once: a 500-link chain has one link mesh
    std::map<std::tuple<int, double, double, double, double, double, std::string>, int> known;
    auto instance = [&](const VisualShape& s) {
        const auto key = std::make_tuple(static_cast<int>(s.kind), s.size.x(), s.size.y(), s.size.z(), s.radius,
                                         s.length, s.mesh_file);
        auto it = known.find(key);
        if (it == known.end()) {
            it = known.emplace(key, static_cast<int>(out.meshes.size())).first;
            out.meshes.push_back(shape_mesh(s, detail));
        }
        ShapeInstance i;
        i.mesh = it->second;
        i.position = s.position;
        i.rotation = Eigen::Quaterniond(s.rotation).normalized();
        i.scale = s.scale;
        i.color = s.color;
        return i;
    };
    for (const auto& shapes : scene.bodies) {
        out.bodies.emplace_back();
        for (const auto& s : shapes) out.bodies.back().push_back(instance(s));
    }
    for (const auto& s : scene.ground) out.ground.push_back(instance(s));
    if (!scene.connectors.empty()) {
        out.connector_mesh = static_cast<int>(out.meshes.size());
        out.meshes.push_back(cylinder(1.0, 0.0, 1.0, detail));
        out.meshes.back().update_bounds();
    }
    return out;
}

}  // namespace mbd::viewer
