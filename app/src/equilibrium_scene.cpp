// The equilibrium scene of `mbd statics --output` (see equilibrium_scene.hpp), written from
// the scene document the Model holds: the scene file is not read again.
#include <mbd/app/equilibrium_scene.hpp>

#include <mbd/sdk/params.hpp>
#include <mbd/sdk/rotation.hpp>

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace mbd {

namespace {

// Keys written first, in this order (the order of docs/scene-format.md); the rest follow
// alphabetically, as the document keeps them.
const char* const kLeadingKeys[] = {"name", "type", "dimension", "gravity", "bodies", "joints", "forces", "drivers"};

// The Param tree back as YAML: scalars as their text (the loader reads only the text, so
// the scene reads back the same), lists of scalars in flow style ([x, y]).
YAML::Node yaml_of(const Param& p) {
    if (p.is_scalar()) return YAML::Node(p.text);
    if (p.is_list()) {
        YAML::Node list(YAML::NodeType::Sequence);
        bool scalars = true;
        for (const Param& item : p.items) {
            list.push_back(yaml_of(item));
            scalars = scalars && item.is_scalar();
        }
        if (scalars) list.SetStyle(YAML::EmitterStyle::Flow);
        return list;
    }
    YAML::Node map(YAML::NodeType::Map);
    for (const char* key : kLeadingKeys)
        if (const auto it = p.fields.find(key); it != p.fields.end()) map[key] = yaml_of(it->second);
    for (const auto& field : p.fields) {
        const std::string& key = field.first;  // a plain name: C++17 lambdas cannot capture structured bindings
        if (std::find_if(std::begin(kLeadingKeys), std::end(kLeadingKeys), [&](const char* k) { return key == k; }) ==
            std::end(kLeadingKeys))
            map[key] = yaml_of(field.second);
    }
    return map;
}

// Each body's position and orientation at the equilibrium, its initial velocities removed.
void place_bodies(YAML::Node bodies, const Model& model, const State& state) {
    const bool planar = model.dimension == Dimension::Planar;
    for (std::size_t k = 0; k < bodies.size() && static_cast<int>(k) < model.body_count(); ++k) {
        YAML::Node b = bodies[k];
        if (planar) {
            const int o = 3 * static_cast<int>(k);
            YAML::Node pos;
            pos.push_back(state.q[o]);
            pos.push_back(state.q[o + 1]);
            pos.SetStyle(YAML::EmitterStyle::Flow);
            b["position"] = pos;
            b["angle"] = state.q[o + 2];
        } else {
            const int o = 7 * static_cast<int>(k);
            YAML::Node pos, ep, orientation;
            for (int i = 0; i < 3; ++i) pos.push_back(state.q[o + i]);
            for (int i = 0; i < 4; ++i) ep.push_back(state.q[o + 3 + i]);
            pos.SetStyle(YAML::EmitterStyle::Flow);
            ep.SetStyle(YAML::EmitterStyle::Flow);
            orientation["euler_parameters"] = ep;
            orientation.SetStyle(YAML::EmitterStyle::Flow);
            b["position"] = pos;
            b["orientation"] = orientation;
        }
        b.remove("velocity");
        b.remove("angular_velocity");
    }
}

// Joint (and world-frame force) points and axes describe the scene's initial
// configuration: move them with the bodies, from the markers of the first
// non-ground body, so that the markers stay where they are on the bodies.
class FrameMover {
public:
    FrameMover(const Model& model, const State& state)
        : state_(state), planar_(model.dimension == Dimension::Planar) {}

    void move(YAML::Node node, const std::vector<int>& element_bodies, const std::vector<Marker>& markers,
              bool always_point) const {
        for (size_t k = 0; k < element_bodies.size() && k < markers.size(); ++k) {
            const int b = element_bodies[k];
            if (b < 0) continue;
            Mat3 A;
            Vec3 R;
            pose(b, A, R);
            Vec3 u = markers[k].u_bar;
            if (planar_) u.z() = 0.0;
            if (always_point || node["point"]) node["point"] = list(R + A * u);
            const Mat3 W = planar_ ? Mat3(A * Eigen::AngleAxisd(markers[k].angle, Vec3::UnitZ()).toRotationMatrix())
                                   : Mat3(A * markers[k].A_bar);
            write_axes(node, W);
            return;
        }
    }

private:
    void pose(int b, Mat3& A, Vec3& R) const {
        if (planar_) {
            R = Vec3(state_.q[3 * b], state_.q[3 * b + 1], 0.0);
            A = Mat3::Identity();
            A.topLeftCorner<2, 2>() = planar_rotation(state_.q[3 * b + 2]);
        } else {
            R = state_.q.segment<3>(7 * b);
            A = rotation_from_euler_parameters(Vec4(state_.q.segment<4>(7 * b + 3)).normalized());
        }
    }
    YAML::Node list(const Vec3& v) const {
        YAML::Node n;
        for (int i = 0; i < (planar_ ? 2 : 3); ++i) n.push_back(v[i]);
        n.SetStyle(YAML::EmitterStyle::Flow);
        return n;
    }
    // the axes the node has, from the marker's world axes W
    void write_axes(YAML::Node node, const Mat3& W) const {
        if (planar_) {
            if (node["axis"]) node["axis"] = list(W.col(0));
            return;
        }
        if (node["axis"]) node["axis"] = list(W.col(2));
        if (node["x_axis"]) node["x_axis"] = list(W.col(0));
        if (node["axes"]) {
            YAML::Node axes;
            axes.push_back(list(W.col(2)));
            axes.push_back(list(W.col(0)));
            axes.SetStyle(YAML::EmitterStyle::Flow);
            node["axes"] = axes;
        }
    }

    const State& state_;
    bool planar_;
};

}  // namespace

std::string equilibrium_scene(const Scene& scene, const State& state) {
    const Model& model = scene.model;
    if (!scene.document) throw std::logic_error("equilibrium_scene: the scene holds no document");
    YAML::Node root = yaml_of(*scene.document);
    place_bodies(root["bodies"], model, state);
    const FrameMover mover(model, state);
    if (YAML::Node joints = root["joints"])
        for (std::size_t k = 0; k < joints.size() && k < model.joints.size(); ++k)
            mover.move(joints[k], model.joints[k].bodies, model.joints[k].markers, true);
    if (YAML::Node forces = root["forces"]) {
        const std::size_t offset = model.gravity.isZero(0.0) ? 0 : 1;  // the core's gravity element comes first
        for (std::size_t k = 0; k < forces.size() && k + offset < model.forces.size(); ++k) {
            YAML::Node f = forces[k];
            const ForceInstance& fi = model.forces[k + offset];
            if (fi.bodies.size() >= 2 && !f["points"] && (f["point"] || f["axis"]))
                mover.move(f, fi.bodies, fi.markers, false);
        }
    }

    YAML::Emitter out;
    out.SetDoublePrecision(17);
    out << root;
    return "# static equilibrium of " + model.source + " (mbd statics)\n" + out.c_str() + '\n';
}

}  // namespace mbd
