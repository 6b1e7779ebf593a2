// The self-contained HTML viewer: the page (viewer/js/page.html with three.js bundled in
// at build time) filled with the scene as JSON and the motion as base64 binary series (see
// column_series), so that it opens offline from file:// and fetches nothing. A scene with
// collision shapes also carries its contacts at each keyframe (json_contacts), which the page
// draws as points and force arrows.
#include <mbd/contact_output.hpp>
#include <mbd/csv.hpp>
#include <mbd/viewer/animation_export.hpp>
#include <mbd/viewer/keyframes.hpp>
#include <mbd/viewer/shape_mesh.hpp>
#include <mbd/visual_joint_markers.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <cstring>
#include <ostream>
#include <sstream>
#include <string_view>

namespace mbd::viewer {

extern const std::string_view kPageBeforeScene;
extern const std::string_view kPageBetween;
extern const std::string_view kPageAfterMotion;

namespace {

// Base64 (RFC 4648) of a byte stream given in pieces of any size.
class Base64Writer {
public:
    explicit Base64Writer(std::ostream& out) : out_(out) { chunk_.reserve(1 << 16); }
    void write(const void* data, size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) {
            carry_[carried_++] = p[i];
            if (carried_ == 3) {
                emit(3);
                carried_ = 0;
            }
        }
    }
    void finish() {
        if (carried_) emit(carried_);
        carried_ = 0;
        out_ << chunk_;
        chunk_.clear();
    }

private:
    void emit(int count) {
        static const char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const unsigned a = carry_[0], b = count > 1 ? carry_[1] : 0, c = count > 2 ? carry_[2] : 0;
        chunk_ += table[a >> 2];
        chunk_ += table[((a & 3) << 4) | (b >> 4)];
        chunk_ += count > 1 ? table[((b & 15) << 2) | (c >> 6)] : '=';
        chunk_ += count > 2 ? table[c & 63] : '=';
        if (chunk_.size() >= (1 << 16) - 4) {
            out_ << chunk_;
            chunk_.clear();
        }
    }
    std::ostream& out_;
    std::string chunk_;
    unsigned char carry_[3] = {0, 0, 0};
    int carried_ = 0;
};

template <class T>
std::string base64_string(const std::vector<T>& values) {
    std::ostringstream s;
    Base64Writer writer(s);
    writer.write(values.data(), values.size() * sizeof(T));
    writer.finish();
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

// JSON has no inf or nan: a number that is not finite would make the page's scene unreadable.
std::string json_number(double x) {
    if (!std::isfinite(x))
        throw InputError("", "the viewer page would hold a number that is not finite (" + std::to_string(x) +
                                 "): the motion is too large to show");
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

// Each flexible body as a tube through its nodes: its node columns (x, y, z; planar z -1), the
// tube's radius (0.04 of the scene's length scale, as thick as the rigid links) and
// its colour. The page rebuilds the tube from the nodes at every frame (viewer.js).
std::string json_flexible(const std::vector<FlexibleNodeColumns>& flexible, double length_scale) {
    std::string out = "[";
    for (size_t k = 0; k < flexible.size(); ++k) {
        out += std::string(k ? "," : "") + "{\"name\":" + json_string(flexible[k].name) + ",\"radius\":" +
               json_number(0.04 * length_scale) + ",\"color\":[0.85,0.55,0.2],\"nodes\":[";
        for (size_t n = 0; n < flexible[k].nodes.size(); ++n) {
            const std::array<int, 3>& c = flexible[k].nodes[n];
            out += std::string(n ? "," : "") + "[" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," +
                   std::to_string(c[2]) + "]";
        }
        out += "]}";
    }
    return out + "]";
}

// Each joint's points on its bodies (body frame) and the derived shape that marks it, if any
// ("marker": {"body", "shape"}): the page's API reports where both are drawn.
std::string json_joints(const Model& model, const std::vector<JointMarkerShape>& markers) {
    std::string out = "[";
    for (size_t j = 0; j < model.joints.size(); ++j) {
        const JointInstance& joint = model.joints[j];
        out += std::string(j ? "," : "") + "{\"name\":" + json_string(joint.name) + ",\"type\":" +
               json_string(joint.type) + ",\"bodies\":[";
        for (size_t k = 0; k < joint.bodies.size(); ++k) out += (k ? "," : "") + std::to_string(joint.bodies[k]);
        out += "],\"points\":[";
        for (size_t k = 0; k < joint.markers.size(); ++k) out += (k ? "," : "") + json_vector(joint.markers[k].u_bar);
        out += "]";
        for (const JointMarkerShape& m : markers)
            if (m.joint == static_cast<int>(j))
                out += ",\"marker\":{\"body\":" + std::to_string(m.body) + ",\"shape\":" + std::to_string(m.shape) + "}";
        out += "}";
    }
    return out + "]";
}

// How the page holds the motion (viewer/js/viewer.js reads the same layout), after the
// keyframe times (float64):
//  - a pose column (a body's x, y, z, angle or e0..e3) as float32 at the keyframes: the rows
//    linear interpolation needs to draw every row within 1e-4 of that coordinate's range
//    (at least 1e-6 of the motion's extent; angles 1e-4 rad, Euler parameters 5e-5), a
//    fraction of a pixel when the whole motion is in view;
//  - every other column as its envelope: the minimum and the maximum over each of
//    kPlotBuckets equal time intervals (NaN where an interval holds no row), all that the
//    plot panel, a few hundred pixels wide, can draw.
// Each column also carries its exact minimum and maximum (the plot's axis).
constexpr size_t kPlotBuckets = 512;
constexpr double kPoseTolerance = 1e-4, kExtentFloor = 1e-6, kAngleTolerance = 1e-4, kEulerTolerance = 5e-5;

struct ColumnLayout {
    bool pose = false;
    size_t offset = 0;  // bytes into the motion data
    double min = 0.0, max = 0.0;
};

struct PageMotion {
    std::vector<size_t> keyframes;
    std::vector<ColumnLayout> columns;
};

PageMotion page_motion(const MotionTable& table, const std::vector<PoseColumns>& poses,
                       const std::vector<FlexibleNodeColumns>& flexible, double extent) {
    PageMotion motion;
    motion.columns.resize(table.columns.size());
    for (size_t k = 0; k < table.columns.size(); ++k) {
        ColumnLayout& c = motion.columns[k];
        c.min = c.max = table.at(0, k);
        for (size_t r = 1; r < table.rows(); ++r) {
            c.min = std::min(c.min, table.at(r, k));
            c.max = std::max(c.max, table.at(r, k));
        }
    }
    std::vector<KeyframeColumn> pose;
    auto add = [&](int column, double tolerance) {
        if (column < 0) return;
        motion.columns[column].pose = true;
        pose.push_back({column, tolerance});
    };
    auto add_position = [&](int c) {
        if (c >= 0) add(c, std::max(kPoseTolerance * (motion.columns[c].max - motion.columns[c].min), kExtentFloor * extent));
    };
    for (const PoseColumns& p : poses) {
        for (int c : {p.x, p.y, p.z}) add_position(c);
        add(p.angle, kAngleTolerance);
        for (int c : p.e) add(c, kEulerTolerance);
    }
    for (const FlexibleNodeColumns& f : flexible)  // each node a point drawn like a mass centre
        for (const std::array<int, 3>& node : f.nodes)
            for (int c : node) add_position(c);
    motion.keyframes = keyframe_rows(table, pose);
    size_t offset = motion.keyframes.size() * sizeof(double);
    for (size_t k = 1; k < motion.columns.size(); ++k) {
        motion.columns[k].offset = offset;
        offset += (motion.columns[k].pose ? motion.keyframes.size() : 2 * kPlotBuckets) * sizeof(float);
    }
    return motion;
}

void write_motion(const MotionTable& table, const PageMotion& motion, std::ostream& out) {
    Base64Writer writer(out);
    std::vector<double> times;
    for (size_t r : motion.keyframes) times.push_back(table.at(r, 0));
    writer.write(times.data(), times.size() * sizeof(double));
    const double t0 = table.at(0, 0), span = std::max(table.at(table.rows() - 1, 0) - t0, 1e-300);
    std::vector<float> values;
    for (size_t k = 1; k < motion.columns.size(); ++k) {
        values.clear();
        if (motion.columns[k].pose) {
            for (size_t r : motion.keyframes) values.push_back(static_cast<float>(table.at(r, k)));
        } else {
            values.assign(2 * kPlotBuckets, std::numeric_limits<float>::quiet_NaN());
            for (size_t r = 0; r < table.rows(); ++r) {
                const double f = (table.at(r, 0) - t0) / span * kPlotBuckets;
                const size_t b = std::min(kPlotBuckets - 1, static_cast<size_t>(f));
                const float v = static_cast<float>(table.at(r, k));
                float& lo = values[2 * b];
                float& hi = values[2 * b + 1];
                if (std::isnan(lo) || v < lo) lo = v;
                if (std::isnan(hi) || v > hi) hi = v;
            }
        }
        writer.write(values.data(), values.size() * sizeof(float));
    }
    writer.finish();
}

// The contacts at each keyframe (contact_output.hpp), when the table holds the motion columns
// (positions and velocities) and the scene has collision shapes: per keyframe a list of
// [x, y, z, nx, ny, nz, normal_force, fx, fy, fz], the point, the unit normal and the forces on
// body j (friction f). The page draws each at the keyframe at or before its time.
std::string json_contacts(const Model& model, const MotionTable& table, const PageMotion& motion) {
    const ContactProbe probe(model);
    const std::vector<std::string> motion_names = motion_columns(model);
    if (!probe.reports() || table.columns.size() < motion_names.size() ||
        !std::equal(motion_names.begin(), motion_names.end(), table.columns.begin()))
        return "null";
    std::string out = "[";
    for (size_t k = 0; k < motion.keyframes.size(); ++k) {
        out += k ? ",[" : "[";
        const std::vector<ContactReport> contacts = probe.contacts_at_row(&table.values[motion.keyframes[k] * table.columns.size()]);
        for (size_t c = 0; c < contacts.size(); ++c) {
            const ContactReport& r = contacts[c];
            out += std::string(c ? "," : "") + "[" + json_number(r.point.x()) + "," + json_number(r.point.y()) + "," +
                   json_number(r.point.z()) + "," + json_number(r.normal.x()) + "," + json_number(r.normal.y()) + "," +
                   json_number(r.normal.z()) + "," + json_number(r.normal_force) + "," +
                   json_number(r.friction_force.x()) + "," + json_number(r.friction_force.y()) + "," +
                   json_number(r.friction_force.z()) + "]";
        }
        out += "]";
    }
    return out + "]";
}

}  // namespace

void write_html(const Model& model, const MotionTable& table, const AnimationOptions& options, std::ostream& out) {
    const std::vector<PoseColumns> columns = match_pose_columns(model, table);
    const std::vector<FlexibleNodeColumns> flexible = match_flexible_columns(model, table);
    std::vector<JointMarkerShape> markers;
    VisualScene scene = build_visual_scene(model, markers);
    const Eigen::AlignedBox3d extent = motion_extent(model, table, columns, flexible);
    fit_ground_grid(model, scene, extent);
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
    j += "],\"joints\":" + json_joints(model, markers) + ",\"poseColumns\":[";
    for (size_t k = 0; k < columns.size(); ++k) {
        const PoseColumns& p = columns[k];
        j += std::string(k ? "," : "") + "{\"x\":" + std::to_string(p.x) + ",\"y\":" + std::to_string(p.y) +
             ",\"z\":" + std::to_string(p.z) + ",\"angle\":" + std::to_string(p.angle) + ",\"e\":[" +
             std::to_string(p.e[0]) + "," + std::to_string(p.e[1]) + "," + std::to_string(p.e[2]) + "," +
             std::to_string(p.e[3]) + "]}";
    }
    const PageMotion motion = page_motion(table, columns, flexible, extent.diagonal().norm());
    j += "],\"flexible\":" + json_flexible(flexible, scene.length_scale) + ",\"columns\":[";
    for (size_t k = 0; k < table.columns.size(); ++k) {
        const ColumnLayout& c = motion.columns[k];
        j += std::string(k ? "," : "") + "{\"name\":" + json_string(table.columns[k]) + ",\"pose\":" +
             (c.pose ? "true" : "false") + ",\"offset\":" + std::to_string(c.offset) + ",\"min\":" +
             json_number(c.min) + ",\"max\":" + json_number(c.max) + "}";
    }
    j += "],\"plotBuckets\":" + std::to_string(kPlotBuckets) + ",\"rows\":" + std::to_string(table.rows()) +
         ",\"keyframes\":" + std::to_string(motion.keyframes.size()) + ",\"plotColumn\":" +
         json_string(options.plot_column.empty() && table.columns.size() > 1 ? table.columns[1] : options.plot_column) +
         ",\"contacts\":" + json_contacts(model, table, motion) + "}";

    out << kPageBeforeScene << j << kPageBetween;
    write_motion(table, motion, out);
    out << kPageAfterMotion;
}

}  // namespace mbd::viewer
