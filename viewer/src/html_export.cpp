// The self-contained HTML viewer: the page (viewer/js/page.html with three.js bundled in
// at build time) filled with the scene as JSON and the motion as base64 float32 values,
// so that it opens offline from file:// and fetches nothing.
#include <mbd/viewer/animation_export.hpp>
#include <mbd/viewer/shape_mesh.hpp>

#include <cstdio>
#include <cstring>
#include <ostream>
#include <sstream>
#include <string_view>

namespace mbd::viewer {

extern const std::string_view kPageBeforeScene;
extern const std::string_view kPageBetween;
extern const std::string_view kPageAfterMotion;

namespace {

void base64(const void* data, size_t bytes, std::ostream& out) {
    static const char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* p = static_cast<const unsigned char*>(data);
    std::string chunk;
    chunk.reserve(1 << 16);
    for (size_t i = 0; i < bytes; i += 3) {
        const unsigned a = p[i], b = i + 1 < bytes ? p[i + 1] : 0, c = i + 2 < bytes ? p[i + 2] : 0;
        chunk += table[a >> 2];
        chunk += table[((a & 3) << 4) | (b >> 4)];
        chunk += i + 1 < bytes ? table[((b & 15) << 2) | (c >> 6)] : '=';
        chunk += i + 2 < bytes ? table[c & 63] : '=';
        if (chunk.size() >= (1 << 16) - 4) {
            out << chunk;
            chunk.clear();
        }
    }
    out << chunk;
}

template <class T>
std::string base64_string(const std::vector<T>& values) {
    std::ostringstream s;
    base64(values.data(), values.size() * sizeof(T), s);
    return s.str();
}

// JSON text; "</" is written "<\/" so that nothing ends the <script> element early.
std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (size_t i = 0; i < s.size(); ++i) {
        const char c = s[i];
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (c == '/' && i > 0 && s[i - 1] == '<') {
            out += "\\/";
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\u%04x", c);
            out += b;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::string json_number(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.9g", x);
    return b;
}

std::string json_vector(const Vec3& v) {
    return "[" + json_number(v.x()) + "," + json_number(v.y()) + "," + json_number(v.z()) + "]";
}

std::string json_shape(const ShapeInstance& s) {
    const Eigen::Quaterniond& q = s.rotation;
    return "{\"mesh\":" + std::to_string(s.mesh) + ",\"position\":" + json_vector(s.position) + ",\"rotation\":[" +
           json_number(q.x()) + "," + json_number(q.y()) + "," + json_number(q.z()) + "," + json_number(q.w()) +
           "],\"scale\":" + json_vector(s.scale) + ",\"color\":" + json_vector(s.color) + "}";
}

std::string json_shapes(const std::vector<ShapeInstance>& shapes) {
    std::string out = "[";
    for (size_t k = 0; k < shapes.size(); ++k) out += (k ? "," : "") + json_shape(shapes[k]);
    return out + "]";
}

}  // namespace

void write_html(const Model& model, const MotionTable& table, const AnimationOptions& options, std::ostream& out) {
    const std::vector<PoseColumns> columns = match_pose_columns(model, table);
    VisualScene scene = build_visual_scene(model);
    fit_ground_grid(model, scene, motion_extent(model, table, columns));
    const SceneMeshes meshes = scene_meshes(scene);
    if (!options.plot_column.empty()) {
        bool found = false;
        for (size_t k = 1; k < table.columns.size(); ++k) found = found || table.columns[k] == options.plot_column;
        if (!found)
            throw InputError(table.source + ":1", "--plot: no column '" + options.plot_column +
                                                      "' in the result (its columns are t, then " +
                                                      table.columns[std::min<size_t>(1, table.columns.size() - 1)] +
                                                      " ...)");
    }

    std::string j = "{\"name\":" + json_string(model.name) + ",\"dimension\":\"" +
                    (model.dimension == Dimension::Planar ? "planar" : "spatial") + "\",\"up\":" + json_vector(scene.up) +
                    ",\"lengthScale\":" + json_number(scene.length_scale) + ",\"grid\":{\"centre\":" +
                    json_vector(scene.grid_centre) + ",\"normal\":" + json_vector(scene.grid_normal) +
                    ",\"size\":" + json_number(scene.grid_size) +
                    ",\"divisions\":" + std::to_string(scene.grid_divisions) + "},\"meshes\":[";
    for (size_t k = 0; k < meshes.meshes.size(); ++k) {
        const TriangleMesh& m = meshes.meshes[k];
        j += std::string(k ? "," : "") + "{\"positions\":\"" + base64_string(m.positions) + "\",\"normals\":\"" +
             base64_string(m.normals) + "\",\"indices\":\"" + base64_string(m.indices) + "\"}";
    }
    j += "],\"bodies\":[";
    for (int b = 0; b < model.body_count(); ++b)
        j += std::string(b ? "," : "") + "{\"name\":" + json_string(model.bodies[b].name) +
             ",\"shapes\":" + json_shapes(meshes.bodies[b]) + "}";
    j += "],\"ground\":" + json_shapes(meshes.ground) + ",\"connectorMesh\":" + std::to_string(meshes.connector_mesh) +
         ",\"connectors\":[";
    for (size_t k = 0; k < scene.connectors.size(); ++k) {
        const VisualConnector& c = scene.connectors[k];
        j += std::string(k ? "," : "") + "{\"name\":" + json_string(c.name) + ",\"bodyA\":" + std::to_string(c.body_a) +
             ",\"bodyB\":" + std::to_string(c.body_b) + ",\"pointA\":" + json_vector(c.point_a) +
             ",\"pointB\":" + json_vector(c.point_b) + ",\"radius\":" + json_number(c.radius) +
             ",\"color\":" + json_vector(c.color) + "}";
    }
    j += "],\"poseColumns\":[";
    for (size_t k = 0; k < columns.size(); ++k) {
        const PoseColumns& p = columns[k];
        j += std::string(k ? "," : "") + "{\"x\":" + std::to_string(p.x) + ",\"y\":" + std::to_string(p.y) +
             ",\"z\":" + std::to_string(p.z) + ",\"angle\":" + std::to_string(p.angle) + ",\"e\":[" +
             std::to_string(p.e[0]) + "," + std::to_string(p.e[1]) + "," + std::to_string(p.e[2]) + "," +
             std::to_string(p.e[3]) + "]}";
    }
    j += "],\"columns\":[";
    for (size_t k = 0; k < table.columns.size(); ++k) j += (k ? "," : "") + json_string(table.columns[k]);
    j += "],\"rows\":" + std::to_string(table.rows()) + ",\"plotColumn\":" +
         json_string(options.plot_column.empty() && table.columns.size() > 1 ? table.columns[1] : options.plot_column) +
         "}";

    out << kPageBeforeScene << j << kPageBetween;
    // the motion as float32, row-major, in slices to bound the memory of the conversion
    const size_t slice = 1 << 15;  // a multiple of 3 bytes keeps the slices' base64 seamless
    std::vector<float> values;
    for (size_t start = 0; start < table.values.size(); start += 3 * slice) {
        const size_t end = std::min(table.values.size(), start + 3 * slice);
        values.assign(table.values.begin() + start, table.values.begin() + end);
        base64(values.data(), values.size() * sizeof(float), out);
    }
    out << kPageAfterMotion;
}

}  // namespace mbd::viewer
