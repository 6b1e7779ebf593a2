// glTF 2.0 binary export (Khronos glTF 2.0 specification; written with tinygltf): a node
// per body carrying its shapes, animated by sampled translation and rotation channels
// (LINEAR), springs as scaled cylinders animated in translation, rotation and scale, and
// the ground with its grid, and each flexible body as a skinned tube (flexible_tube.hpp).
// World axes are the scene's (planar scenes in the x-y plane).
#include <mbd/viewer/animation_export.hpp>
#include <mbd/viewer/flexible_tube.hpp>
#include <mbd/viewer/shape_mesh.hpp>

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <string>
#include <map>

namespace mbd::viewer {
namespace {

// glTF numbers are finite 32-bit floats: `what` names the values in the error otherwise.
void require_finite(const std::vector<float>& values, int components, const std::string& what) {
    for (size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
            throw InputError(what, "value " + std::to_string(i / components + 1) +
                                       " is not a finite 32-bit float (glTF allows none): the motion is too large "
                                       "to animate");
}

class GlbBuilder {
public:
    int view(const void* data, size_t bytes, int target) {
        auto& buffer = model_.buffers[0].data;
        while (buffer.size() % 4) buffer.push_back(0);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = buffer.size();
        v.byteLength = bytes;
        v.target = target;
        const auto* p = static_cast<const unsigned char*>(data);
        buffer.insert(buffer.end(), p, p + bytes);
        model_.bufferViews.push_back(v);
        return static_cast<int>(model_.bufferViews.size() - 1);
    }

    // `what` names the values in the error a non-finite one gets (glTF numbers are finite floats).
    int accessor(const std::vector<float>& values, int type, int components, int target, bool bounds,
                 const std::string& what) {
        require_finite(values, components, what);
        tinygltf::Accessor a;
        a.bufferView = view(values.data(), values.size() * sizeof(float), target);
        a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        a.count = values.size() / components;
        a.type = type;
        if (bounds) {
            a.minValues.assign(components, 1e300);
            a.maxValues.assign(components, -1e300);
            for (size_t i = 0; i < values.size(); ++i) {
                a.minValues[i % components] = std::min(a.minValues[i % components], double(values[i]));
                a.maxValues[i % components] = std::max(a.maxValues[i % components], double(values[i]));
            }
        }
        model_.accessors.push_back(a);
        return static_cast<int>(model_.accessors.size() - 1);
    }

    // Skin joint indices (JOINTS_0): four unsigned shorts per vertex.
    int joints(const std::vector<uint16_t>& values) {
        tinygltf::Accessor a;
        a.bufferView = view(values.data(), values.size() * sizeof(uint16_t), TINYGLTF_TARGET_ARRAY_BUFFER);
        a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
        a.count = values.size() / 4;
        a.type = TINYGLTF_TYPE_VEC4;
        model_.accessors.push_back(a);
        return static_cast<int>(model_.accessors.size() - 1);
    }

    int indices(const std::vector<uint32_t>& values) {
        tinygltf::Accessor a;
        a.bufferView = view(values.data(), values.size() * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        a.count = values.size();
        a.type = TINYGLTF_TYPE_SCALAR;
        model_.accessors.push_back(a);
        return static_cast<int>(model_.accessors.size() - 1);
    }

    int material(const Vec3& color, double metallic, double roughness) {
        const auto key = std::make_tuple(color.x(), color.y(), color.z(), metallic);
        auto it = materials_.find(key);
        if (it != materials_.end()) return it->second;
        tinygltf::Material m;
        m.pbrMetallicRoughness.baseColorFactor = {color.x(), color.y(), color.z(), 1.0};
        m.pbrMetallicRoughness.metallicFactor = metallic;
        m.pbrMetallicRoughness.roughnessFactor = roughness;
        model_.materials.push_back(m);
        return materials_[key] = static_cast<int>(model_.materials.size() - 1);
    }

    // One glTF mesh per (triangle mesh, colour); the vertex data is written once per triangle mesh.
    int mesh(const SceneMeshes& meshes, int index, const Vec3& color) {
        auto key = std::make_tuple(index, color.x(), color.y(), color.z());
        auto it = meshes_.find(key);
        if (it != meshes_.end()) return it->second;
        auto data = vertex_data_.find(index);
        if (data == vertex_data_.end()) {
            const TriangleMesh& m = meshes.meshes[index];
            const int pos = accessor(m.positions, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true,
                                     "mesh " + std::to_string(index) + " positions");
            const int nor = accessor(m.normals, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, false,
                                     "mesh " + std::to_string(index) + " normals");
            data = vertex_data_.emplace(index, std::array<int, 3>{pos, nor, indices(m.indices)}).first;
        }
        tinygltf::Primitive p;
        p.attributes["POSITION"] = data->second[0];
        p.attributes["NORMAL"] = data->second[1];
        p.indices = data->second[2];
        p.mode = TINYGLTF_MODE_TRIANGLES;
        p.material = material(color, 0.1, 0.6);
        tinygltf::Mesh mesh;
        mesh.primitives.push_back(p);
        model_.meshes.push_back(mesh);
        return meshes_[key] = static_cast<int>(model_.meshes.size() - 1);
    }

    int node(tinygltf::Node n) {
        model_.nodes.push_back(std::move(n));
        return static_cast<int>(model_.nodes.size() - 1);
    }

    tinygltf::Model& model() { return model_; }

    GlbBuilder() {
        model_.asset.version = "2.0";
        model_.asset.generator = "mbd animate";
        model_.buffers.emplace_back();
    }

private:
    tinygltf::Model model_;
    std::map<std::tuple<double, double, double, double>, int> materials_;
    std::map<std::tuple<int, double, double, double>, int> meshes_;
    std::map<int, std::array<int, 3>> vertex_data_;
};

std::vector<double> to_vector(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
std::vector<double> to_vector(const Eigen::Quaterniond& q) { return {q.x(), q.y(), q.z(), q.w()}; }

tinygltf::Node shape_node(GlbBuilder& b, const SceneMeshes& meshes, const ShapeInstance& s, const std::string& name) {
    tinygltf::Node n;
    n.name = name;
    n.mesh = b.mesh(meshes, s.mesh, s.color);
    if (!s.position.isZero(0.0)) n.translation = to_vector(s.position);
    if (!s.rotation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs(), 0.0)) n.rotation = to_vector(s.rotation);
    if (s.scale != Vec3::Ones()) n.scale = to_vector(s.scale);
    return n;
}

// The ground grid: lines across `normal`, centred at `centre`.
tinygltf::Node grid_node(GlbBuilder& b, const VisualScene& scene) {
    const Vec3 n = scene.grid_normal;
    const Vec3 u = (std::abs(n.z()) > 0.9 ? Vec3::UnitX() : Vec3::UnitZ()).cross(n).normalized();
    const Vec3 v = n.cross(u);
    std::vector<float> positions;
    const double h = 0.5 * scene.grid_size;
    for (int k = 0; k <= scene.grid_divisions; ++k) {
        const double s = -h + scene.grid_size * k / scene.grid_divisions;
        for (const Vec3& p : {Vec3(scene.grid_centre + s * u - h * v), Vec3(scene.grid_centre + s * u + h * v),
                              Vec3(scene.grid_centre - h * u + s * v), Vec3(scene.grid_centre + h * u + s * v)})
            for (int i = 0; i < 3; ++i) positions.push_back(static_cast<float>(p[i]));
    }
    tinygltf::Primitive p;
    p.attributes["POSITION"] = b.accessor(positions, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true, "grid");
    p.mode = TINYGLTF_MODE_LINE;
    p.material = b.material(Vec3(0.55, 0.55, 0.58), 0.0, 1.0);
    tinygltf::Mesh mesh;
    mesh.name = "grid";
    mesh.primitives.push_back(p);
    b.model().meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = "grid";
    node.mesh = static_cast<int>(b.model().meshes.size() - 1);
    return node;
}

// A connector's cylinder (z from 0 to 1, radius 1) stretched from point a to point b.
void connector_pose(const VisualConnector& c, const BodyPose* a, const BodyPose* b, Vec3& t, Eigen::Quaterniond& r,
                    Vec3& s) {
    const Vec3 pa = a ? Vec3(a->position + a->rotation * c.point_a) : c.point_a;
    const Vec3 pb = b ? Vec3(b->position + b->rotation * c.point_b) : c.point_b;
    const Vec3 d = pb - pa;
    t = pa;
    r = d.norm() > 0 ? Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d) : Eigen::Quaterniond::Identity();
    s = Vec3(c.radius, c.radius, std::max(d.norm(), 1e-9));
}

void push(std::vector<float>& out, const Vec3& v) {
    for (int k = 0; k < 3; ++k) out.push_back(static_cast<float>(v[k]));
}
// Keeps consecutive quaternions in one hemisphere so that interpolation takes the short way.
void push(std::vector<float>& out, Eigen::Quaterniond q, size_t row) {
    if (row > 0) {
        const size_t n = out.size();
        const Eigen::Quaterniond prev(out[n - 1], out[n - 4], out[n - 3], out[n - 2]);
        if (prev.dot(q) < 0) q.coeffs() = -q.coeffs();
    }
    out.push_back(static_cast<float>(q.x()));
    out.push_back(static_cast<float>(q.y()));
    out.push_back(static_cast<float>(q.z()));
    out.push_back(static_cast<float>(q.w()));
}

}  // namespace

namespace {

// The animation's channels: each node's samples (translation, rotation, scale) against the
// rows' times, linearly interpolated.
struct MotionChannels {
    GlbBuilder& b;
    const std::string& source;
    tinygltf::Animation animation;
    int time_accessor = -1;

    void add(int node, const char* path, const std::vector<float>& values, int type, int components) {
        tinygltf::AnimationSampler s;
        s.input = time_accessor;
        s.output = b.accessor(values, type, components, 0, false, source + ": " + b.model().nodes[node].name + " " + path);
        s.interpolation = "LINEAR";
        animation.samplers.push_back(s);
        tinygltf::AnimationChannel c;
        c.sampler = static_cast<int>(animation.samplers.size() - 1);
        c.target_node = node;
        c.target_path = path;
        animation.channels.push_back(c);
    }
};

// A body's node with its shapes, posed at the first row; its motion added to `motion` (if any).
int body_node(GlbBuilder& b, const Model& model, const MotionTable& table, const PoseColumns& columns,
              const SceneMeshes& meshes, int body, MotionChannels* motion) {
    tinygltf::Node n;
    n.name = model.bodies[body].name;
    for (size_t k = 0; k < meshes.bodies[body].size(); ++k)
        n.children.push_back(b.node(shape_node(b, meshes, meshes.bodies[body][k], n.name + "/shape" + std::to_string(k))));
    const BodyPose first = body_pose(table, columns, 0);
    n.translation = to_vector(first.position);
    n.rotation = to_vector(first.rotation);
    const int index = b.node(n);
    if (!motion) return index;
    std::vector<float> translation, rotation;
    translation.reserve(3 * table.rows());
    rotation.reserve(4 * table.rows());
    for (size_t r = 0; r < table.rows(); ++r) {
        const BodyPose pose = body_pose(table, columns, r);
        push(translation, pose.position);
        push(rotation, pose.rotation, r);
    }
    motion->add(index, "translation", translation, TINYGLTF_TYPE_VEC3, 3);
    motion->add(index, "rotation", rotation, TINYGLTF_TYPE_VEC4, 4);
    return index;
}

// A connector's node (a rod between its two bodies' points), placed, turned and stretched at
// every row; its motion added to `motion` (if any).
int connector_node(GlbBuilder& b, const MotionTable& table, const std::vector<PoseColumns>& columns,
                   const SceneMeshes& meshes, const VisualConnector& c, MotionChannels* motion) {
    std::vector<float> translation, rotation, scale;
    for (size_t r = 0; r < table.rows(); ++r) {
        Vec3 t, s;
        Eigen::Quaterniond q;
        const BodyPose a = c.body_a == kGround ? BodyPose() : body_pose(table, columns[c.body_a], r);
        const BodyPose b_pose = c.body_b == kGround ? BodyPose() : body_pose(table, columns[c.body_b], r);
        connector_pose(c, c.body_a == kGround ? nullptr : &a, c.body_b == kGround ? nullptr : &b_pose, t, q, s);
        push(translation, t);
        push(rotation, q, r);
        push(scale, s);
    }
    require_finite(translation, 3, table.source + ": connector " + c.name + " translation");
    require_finite(rotation, 4, table.source + ": connector " + c.name + " rotation");
    require_finite(scale, 3, table.source + ": connector " + c.name + " scale");
    tinygltf::Node n;
    n.name = c.name;
    n.mesh = b.mesh(meshes, meshes.connector_mesh, c.color);
    n.translation = {translation[0], translation[1], translation[2]};
    n.rotation = {rotation[0], rotation[1], rotation[2], rotation[3]};
    n.scale = {scale[0], scale[1], scale[2]};
    const int index = b.node(n);
    if (!motion) return index;
    motion->add(index, "translation", translation, TINYGLTF_TYPE_VEC3, 3);
    motion->add(index, "rotation", rotation, TINYGLTF_TYPE_VEC4, 4);
    motion->add(index, "scale", scale, TINYGLTF_TYPE_VEC3, 3);
    return index;
}

// A flexible body drawn as a skinned tube (issue 40): a ring of kTubeSides vertices around each
// centreline point (flexible_tube.hpp), every vertex bound wholly to its point's joint node, and
// the joints animated in translation and rotation, so the mesh follows the nodes at every row.
// Skinning rather than morph targets: it stores 7 floats per centreline point and row, where
// morph targets would store every vertex at every row. The mesh is bound at the first row (its
// vertices where the tube is then; inverse bind matrices the joints' inverse poses there). The
// tube's node is a root of the scene, as glTF wants of a skinned mesh (its parents' transforms
// would not apply); the joints sit under a node named after the body.
constexpr int kTubeSides = 12;

Eigen::Matrix4d inverse_pose(const TubeFrame& f) {
    const Eigen::Matrix3d rt = f.rotation.toRotationMatrix().transpose();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = rt;
    m.topRightCorner<3, 1>() = -rt * f.position;
    return m;
}

// The tube's mesh bound at the frames `bind`; its inverse bind matrices' accessor in `inverse_bind`.
int tube_mesh(GlbBuilder& b, const std::vector<TubeFrame>& bind, double radius, const std::string& name,
              int& inverse_bind) {
    const size_t points = bind.size();
    std::vector<float> positions, normals, weights, ibm;
    std::vector<uint16_t> joints;
    std::vector<uint32_t> triangles;
    for (size_t i = 0; i < points; ++i) {
        for (int j = 0; j < kTubeSides; ++j) {
            const double phi = 2.0 * M_PI * j / kTubeSides;
            const Vec3 radial = bind[i].rotation * Vec3(std::cos(phi), std::sin(phi), 0.0);
            push(positions, Vec3(bind[i].position + radius * radial));
            push(normals, radial.normalized());
            joints.insert(joints.end(), {static_cast<uint16_t>(i), 0, 0, 0});
            weights.insert(weights.end(), {1.0f, 0.0f, 0.0f, 0.0f});
            if (i + 1 == points) continue;
            const uint32_t a = static_cast<uint32_t>(i * kTubeSides + j);
            const uint32_t next = static_cast<uint32_t>(i * kTubeSides + (j + 1) % kTubeSides);
            triangles.insert(triangles.end(), {a, next, a + kTubeSides, next, next + kTubeSides, a + kTubeSides});
        }
        const Eigen::Matrix4d m = inverse_pose(bind[i]);
        for (int c = 0; c < 4; ++c)  // column-major; the last row exactly (0, 0, 0, 1)
            for (int r = 0; r < 4; ++r) ibm.push_back(r == 3 ? (c == 3 ? 1.0f : 0.0f) : static_cast<float>(m(r, c)));
    }
    tinygltf::Primitive p;
    p.attributes["POSITION"] = b.accessor(positions, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true,
                                          name + " tube positions");
    p.attributes["NORMAL"] = b.accessor(normals, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, false,
                                        name + " tube normals");
    p.attributes["JOINTS_0"] = b.joints(joints);
    p.attributes["WEIGHTS_0"] = b.accessor(weights, TINYGLTF_TYPE_VEC4, 4, TINYGLTF_TARGET_ARRAY_BUFFER, false,
                                           name + " tube weights");
    if (!triangles.empty()) p.indices = b.indices(triangles);
    p.mode = triangles.empty() ? TINYGLTF_MODE_POINTS : TINYGLTF_MODE_TRIANGLES;
    p.material = b.material(Vec3(0.85, 0.55, 0.2), 0.1, 0.6);  // the page's tube colour
    tinygltf::Mesh mesh;
    mesh.name = name;
    mesh.primitives.push_back(p);
    b.model().meshes.push_back(mesh);
    inverse_bind = b.accessor(ibm, TINYGLTF_TYPE_MAT4, 16, 0, false, name + " bind");
    return static_cast<int>(b.model().meshes.size() - 1);
}

// The joint's name: a node's ("NAME/node3") or a point between two nodes ("NAME/segment3.1").
std::string tube_joint_name(const std::string& body, size_t point) {
    const size_t segment = point / kTubePointsPerSegment, inner = point % kTubePointsPerSegment;
    return body + (inner == 0 ? "/node" + std::to_string(segment)
                              : "/segment" + std::to_string(segment) + "." + std::to_string(inner));
}

// Adds the body's joints under `root` and returns the tube's node (a scene root).
int flexible_tube(GlbBuilder& b, const MotionTable& table, const FlexibleNodeColumns& f, double radius,
                  MotionChannels* motion, tinygltf::Node& root) {
    std::vector<std::vector<TubeFrame>> rows(table.rows());
    std::vector<Vec3> nodes(f.nodes.size());
    for (size_t r = 0; r < table.rows(); ++r) {
        for (size_t k = 0; k < nodes.size(); ++k) nodes[k] = node_position(table, f.nodes[k], r);
        rows[r] = tube_frames(tube_centreline(nodes), r > 0 ? rows[r - 1] : std::vector<TubeFrame>{});
    }
    const size_t points = rows[0].size();
    if (points > 65535)
        throw InputError(table.source, "flexible body '" + f.name + "' has too many nodes for a glTF skin");
    tinygltf::Node group;
    group.name = f.name;
    tinygltf::Skin skin;
    skin.name = f.name;
    for (size_t i = 0; i < points; ++i) {
        tinygltf::Node joint;
        joint.name = tube_joint_name(f.name, i);
        joint.translation = to_vector(rows[0][i].position);
        joint.rotation = to_vector(rows[0][i].rotation);
        const int index = b.node(joint);
        skin.joints.push_back(index);
        group.children.push_back(index);
        if (!motion) continue;
        std::vector<float> translation, rotation;
        for (size_t r = 0; r < rows.size(); ++r) {
            push(translation, rows[r][i].position);
            push(rotation, rows[r][i].rotation, r);
        }
        motion->add(index, "translation", translation, TINYGLTF_TYPE_VEC3, 3);
        motion->add(index, "rotation", rotation, TINYGLTF_TYPE_VEC4, 4);
    }
    skin.skeleton = b.node(group);
    root.children.push_back(skin.skeleton);
    tinygltf::Node tube;
    tube.name = f.name + "/tube";
    tube.mesh = tube_mesh(b, rows[0], radius, f.name, skin.inverseBindMatrices);
    b.model().skins.push_back(skin);
    tube.skin = static_cast<int>(b.model().skins.size() - 1);
    return b.node(tube);
}

}  // namespace

void write_glb(const Model& model, const MotionTable& table, std::ostream& out) {
    const std::vector<PoseColumns> columns = match_pose_columns(model, table);
    const std::vector<FlexibleNodeColumns> flexible = match_flexible_columns(model, table);
    VisualScene scene = build_visual_scene(model);
    fit_ground_grid(model, scene, motion_extent(model, table, columns, flexible));
    const SceneMeshes meshes = scene_meshes(scene);
    const size_t rows = table.rows();
    const bool animated = rows > 1;

    GlbBuilder b;
    tinygltf::Node root;
    root.name = model.name.empty() ? "mbd" : model.name;

    tinygltf::Node ground;
    ground.name = "ground";
    ground.children.push_back(b.node(grid_node(b, scene)));
    for (size_t k = 0; k < meshes.ground.size(); ++k)
        ground.children.push_back(b.node(shape_node(b, meshes, meshes.ground[k], "ground/shape" + std::to_string(k))));
    root.children.push_back(b.node(ground));

    MotionChannels motion{b, table.source, {}, -1};
    motion.animation.name = "motion";
    if (animated) {
        std::vector<float> times(rows);
        for (size_t r = 0; r < rows; ++r) times[r] = static_cast<float>(table.at(r, 0));
        motion.time_accessor = b.accessor(times, TINYGLTF_TYPE_SCALAR, 1, 0, true, table.source + ": column 't'");
    }
    MotionChannels* channels = animated ? &motion : nullptr;

    // the binary chunk: about 7 floats per body (and tube joint) and row
    size_t tube_joints = 0;
    for (const FlexibleNodeColumns& f : flexible) tube_joints += f.nodes.size() * kTubePointsPerSegment;
    b.model().buffers[0].data.reserve(
        rows * ((model.body_count() + tube_joints) * 7 + scene.connectors.size() * 10 + 1) * 4 + (1 << 20));
    for (int body = 0; body < model.body_count(); ++body)
        root.children.push_back(body_node(b, model, table, columns[body], meshes, body, channels));
    for (const VisualConnector& c : scene.connectors)
        root.children.push_back(connector_node(b, table, columns, meshes, c, channels));
    std::vector<int> tubes;  // roots of the scene beside `root` (skinned meshes)
    for (const FlexibleNodeColumns& f : flexible)  // the page's radius: as thick as the rigid links
        tubes.push_back(flexible_tube(b, table, f, 0.04 * scene.length_scale, channels, root));

    const int root_index = b.node(root);
    tinygltf::Scene gltf_scene;
    gltf_scene.name = root.name;
    gltf_scene.nodes.push_back(root_index);
    gltf_scene.nodes.insert(gltf_scene.nodes.end(), tubes.begin(), tubes.end());
    b.model().scenes.push_back(gltf_scene);
    b.model().defaultScene = 0;
    if (animated) b.model().animations.push_back(motion.animation);
    b.model().buffers[0].data.resize((b.model().buffers[0].data.size() + 3) / 4 * 4, 0);

    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&b.model(), out, false, true))
        throw std::runtime_error("the glTF writer failed");
}

}  // namespace mbd::viewer
