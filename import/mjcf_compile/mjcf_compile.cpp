// MJCF compiled with placeholders for its missing mesh and texture files (mjcf_compile.hpp).
#include <mbd/import/mjcf_compile.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <regex>

namespace mbd::import {

namespace {

using Bytes = std::string;

// The placeholder mesh: a tetrahedron with edges `edge` along x, y, z from the origin, faces
// wound outward (MuJoCo computes its volume and inertia from them).
constexpr float kVertices[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
constexpr int kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

// Binary STL: 80-byte header, triangle count, then per triangle a normal, 3 vertices, 2 bytes.
Bytes stl_tetrahedron(float edge) {
    Bytes out(80, ' ');
    const std::uint32_t count = 4;
    out.append(reinterpret_cast<const char*>(&count), 4);
    for (const auto& face : kFaces) {
        const float normal[3] = {0, 0, 0};  // MuJoCo recomputes normals from the vertices
        out.append(reinterpret_cast<const char*>(normal), sizeof normal);
        for (int v : face)
            for (float x : kVertices[v]) {
                const float scaled = edge * x;
                out.append(reinterpret_cast<const char*>(&scaled), sizeof scaled);
            }
        out.append(2, '\0');
    }
    return out;
}

Bytes obj_tetrahedron(float edge) {
    std::string out;
    for (const auto& v : kVertices)
        out += "v " + std::to_string(edge * v[0]) + " " + std::to_string(edge * v[1]) + " " + std::to_string(edge * v[2]) + "\n";
    for (const auto& f : kFaces) out += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
    return out;
}

// A 1x1 grey RGB PNG (signature, IHDR, IDAT, IEND with their CRCs), for a missing texture.
const unsigned char kPixelPng[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00,
    0x0c, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x68, 0x68, 0x68, 0x00, 0x00, 0x03, 0x04, 0x01, 0x81, 0x4b,
    0xd3, 0xd2, 0x10, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

// The placeholder for a file by its extension at size `scale` (1 or 2); empty: none for that kind.
Bytes placeholder(const std::string& path, float scale) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    const float edge = 0.01f * scale;
    if (ext == ".stl") return stl_tetrahedron(edge);
    if (ext == ".obj") return obj_tetrahedron(edge);
    if (ext == ".png") return Bytes(reinterpret_cast<const char*>(kPixelPng), sizeof kPixelPng);
    return {};
}

std::string one_line(std::string message) {
    while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) message.pop_back();
    for (char& c : message)
        if (c == '\n') c = ' ';
    return message;
}

using ModelPtr = std::unique_ptr<mjModel, void (*)(mjModel*)>;

// One compilation with the placeholders of `missing` at `scale` in a fresh VFS.
ModelPtr compile_with(const std::filesystem::path& file, const std::vector<MissingAsset>& missing, float scale,
                      std::string& error) {
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    for (const MissingAsset& asset : missing) {
        const Bytes bytes = placeholder(asset.path, scale);
        if (mj_makeEmptyFileVFS(vfs.get(), asset.path.c_str(), static_cast<int>(bytes.size())) != 0)
            continue;  // the same file name twice: its placeholder is there already
        std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), asset.path.c_str())], bytes.data(), bytes.size());
    }
    char message[1000] = "";
    ModelPtr model(mj_loadXML(file.c_str(), vfs.get(), message, sizeof message), mj_deleteModel);
    mj_deleteVFS(vfs.get());
    error = model ? "" : one_line(message);
    return model;
}

// The `file="..."` of line `line` of `file` (MuJoCo's message for a missing PNG texture names its
// line, not its file); empty when that line has none.
std::string file_attribute_at(const std::filesystem::path& file, const std::string& line) {
    std::ifstream in(file);
    std::string text;
    for (long k = std::stol(line); k > 0 && std::getline(in, text);) --k;
    static const std::regex attribute("\\bfile=\"([^\"]+)\"");
    std::smatch match;
    return in && std::regex_search(text, match, attribute) ? match[1].str() : "";
}

// The file MuJoCo's message says it could not open, when it is absent from disk and a placeholder
// exists for its kind; false otherwise (then the message is the error).
bool missing_asset(const std::filesystem::path& file, const std::string& message, MissingAsset& asset) {
    static const std::regex cannot_open("could not (?:open|parse) (?:STL|OBJ) file '([^']+)'");
    static const std::regex png_absent("PNG file load error 'failed to open file for reading'");
    static const std::regex object("Object name = ([^,]*), id = [0-9]+, line = ([0-9]+)");
    std::smatch opened, named;
    if (std::regex_search(message, named, object)) asset.object = named[1].str(), asset.line = named[2].str();
    if (std::regex_search(message, opened, cannot_open)) {
        asset.kind = "mesh";
        asset.path = opened[1].str();
        if (std::filesystem::exists(asset.path)) return false;  // there, but MuJoCo cannot read it
    } else if (std::regex_search(message, png_absent) && !asset.line.empty()) {
        asset.kind = "texture";
        asset.path = file_attribute_at(file, asset.line);
    } else {
        return false;
    }
    return !asset.path.empty() && !placeholder(asset.path, 1).empty();
}

bool differs(const mjtNum* a, const mjtNum* b, int n) {
    for (int k = 0; k < n; ++k)
        if (std::abs(a[k] - b[k]) > 1e-12 * (1.0 + std::abs(a[k]))) return true;
    return false;
}

// A body's inertia tensor in its own frame (MuJoCo keeps principal moments and their frame).
void body_inertia(const mjModel* m, int b, mjtNum tensor[9]) {
    mjtNum axes[9];
    mju_quat2Mat(axes, m->body_iquat + 4 * b);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            tensor[3 * i + j] = 0;
            for (int k = 0; k < 3; ++k) tensor[3 * i + j] += axes[3 * i + k] * m->body_inertia[3 * b + k] * axes[3 * j + k];
        }
}

bool body_differs(const mjModel* a, const mjModel* b, int body) {
    mjtNum ia[9], ib[9];
    body_inertia(a, body, ia);
    body_inertia(b, body, ib);
    return differs(a->body_mass + body, b->body_mass + body, 1) || differs(a->body_ipos + 3 * body, b->body_ipos + 3 * body, 3) ||
           differs(ia, ib, 9);
}

// Meshes whose vertices differ between the two compilations: those read from placeholders.
std::vector<bool> placeholder_meshes(const mjModel* a, const mjModel* b) {
    std::vector<bool> out(a->nmesh, false);
    for (int k = 0; k < a->nmesh; ++k) {
        const int n = a->mesh_vertnum[k];
        const float *va = a->mesh_vert + 3 * a->mesh_vertadr[k], *vb = b->mesh_vert + 3 * b->mesh_vertadr[k];
        out[k] = n != b->mesh_vertnum[k] || !std::equal(va, va + 3 * n, vb);
    }
    return out;
}

std::string name_of(const mjModel* m, int type, int id, const char* kind) {
    const char* name = mj_id2name(m, type, id);
    return std::string(kind) + ((name && *name) ? " '" + std::string(name) + "'" : " #" + std::to_string(id));
}

// Geoms whose geometry is a placeholder's: a placeholder mesh, or a size or pose fitted to one.
std::vector<int> placeholder_geoms(const mjModel* a, const mjModel* b) {
    const std::vector<bool> meshes = placeholder_meshes(a, b);
    std::vector<int> out;
    for (int g = 0; g < a->ngeom; ++g) {
        const bool mesh = a->geom_type[g] == mjGEOM_MESH && a->geom_dataid[g] >= 0 && meshes[a->geom_dataid[g]];
        if (mesh || differs(a->geom_size + 3 * g, b->geom_size + 3 * g, 3) || differs(a->geom_pos + 3 * g, b->geom_pos + 3 * g, 3) ||
            differs(a->geom_quat + 4 * g, b->geom_quat + 4 * g, 4))
            out.push_back(g);
    }
    return out;
}

// The refusal of the first body whose mass, mass centre or inertia a placeholder changes.
std::string inertia_from_missing_mesh(const MjcfCompilation& c, const mjModel* other) {
    const mjModel* m = c.model.get();
    for (int b = 1; b < m->nbody; ++b) {
        if (!body_differs(m, other, b)) continue;
        std::string meshes, files;  // the body's placeholder meshes, and the files MuJoCo named for them
        for (int g : c.placeholder_geoms) {
            if (m->geom_bodyid[g] != b || m->geom_type[g] != mjGEOM_MESH) continue;
            const char* mesh = mj_id2name(m, mjOBJ_MESH, m->geom_dataid[g]);
            meshes += (meshes.empty() ? "" : ", ") + name_of(m, mjOBJ_MESH, m->geom_dataid[g], "mesh");
            for (const MissingAsset& asset : c.missing)
                if (mesh && asset.object == mesh) files += (files.empty() ? "" : ", ") + asset.path;
        }
        if (files.empty())  // its meshes reuse files named for other meshes
            for (const MissingAsset& asset : c.missing) files += (files.empty() ? "" : ", ") + asset.path;
        return name_of(m, mjOBJ_BODY, b, "body") + " takes its inertia from a mesh that is not there (" + meshes +
               "; missing files: " + files + "): MuJoCo computes the mass and inertia of a body without <inertial> from its "
               "geoms (inertiafromgeom), so its dynamics would be made up; give the body an <inertial> element or supply the mesh files";
    }
    return "";
}

}  // namespace

MjcfCompilation compile_mjcf(const std::filesystem::path& file) {
    MjcfCompilation c;
    for (int attempt = 0; attempt <= mjMAXVFS; ++attempt) {  // one more placeholder per attempt
        c.model = compile_with(file, c.missing, 1, c.error);
        MissingAsset asset;
        if (c.model || !missing_asset(file, c.error, asset)) break;
        const auto same = [&](const MissingAsset& earlier) { return earlier.path == asset.path; };
        if (std::any_of(c.missing.begin(), c.missing.end(), same)) break;  // its placeholder did not help
        c.missing.push_back(asset);
    }
    if (!c.model || c.missing.empty()) return c;
    std::string error;
    const ModelPtr twice = compile_with(file, c.missing, 2, error);
    if (!twice) {
        c.error = error;
        c.model.reset();
        return c;
    }
    c.placeholder_geoms = placeholder_geoms(c.model.get(), twice.get());
    c.error = inertia_from_missing_mesh(c, twice.get());
    c.inertia_from_missing_mesh = !c.error.empty();
    if (c.inertia_from_missing_mesh) c.model.reset();
    return c;
}

namespace {

// "geom #3 of body 'link0', geom 'pad' of body 'hand'": the placeholder geoms of mesh `mesh`.
std::string geoms_of_mesh(const MjcfCompilation& c, int mesh) {
    const mjModel* m = c.model.get();
    std::string out;
    for (int g : c.placeholder_geoms)
        if (m->geom_type[g] == mjGEOM_MESH && m->geom_dataid[g] == mesh)
            out += (out.empty() ? "" : ", ") + name_of(m, mjOBJ_GEOM, g, "geom") + " of " +
                   name_of(m, mjOBJ_BODY, m->geom_bodyid[g], "body");
    return out.empty() ? "no geom" : out;
}

}  // namespace

std::vector<std::string> describe_missing(const MjcfCompilation& c, std::vector<std::string>& others) {
    const mjModel* m = c.model.get();
    std::vector<std::string> out;
    std::vector<bool> listed(m ? m->nmesh : 0, false);
    for (const MissingAsset& asset : c.missing) {
        std::string entry = asset.path + " (" + asset.kind + " '" + asset.object + "', line " + asset.line;
        const int mesh = (m && asset.kind == "mesh") ? mj_name2id(m, mjOBJ_MESH, asset.object.c_str()) : -1;
        if (mesh >= 0) entry += ": " + geoms_of_mesh(c, mesh), listed[mesh] = true;
        out.push_back(entry + ")");
    }
    for (int g : c.placeholder_geoms) {  // meshes reading a file listed above, and fitted primitives
        const int mesh = m->geom_type[g] == mjGEOM_MESH ? m->geom_dataid[g] : -1;
        if (mesh >= 0 && listed[mesh]) continue;
        if (mesh >= 0) {
            listed[mesh] = true;
            others.push_back(name_of(m, mjOBJ_MESH, mesh, "mesh") + " (" + geoms_of_mesh(c, mesh) + ")");
        } else {
            others.push_back(name_of(m, mjOBJ_GEOM, g, "geom") + " of " + name_of(m, mjOBJ_BODY, m->geom_bodyid[g], "body") +
                          " (fitted to a missing mesh)");
        }
    }
    return out;
}

}  // namespace mbd::import
