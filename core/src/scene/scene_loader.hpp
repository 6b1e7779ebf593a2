// The scene loader's internals (core/src/scene/scene.cpp: the top level, bodies and joints;
// core/src/scene/scene_elements.cpp: forces, drivers, joint limits, actuators and gravity).
// Not installed: the public interface is mbd/scene.hpp.
#pragma once

#include <mbd/plugin_description.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/suggest.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/visual.hpp>

#include "scene/scene_source.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

namespace mbd::scene_detail {

std::string quote(const std::string& s);
std::string join(const std::vector<std::string>& items, const std::string& sep = ", ");
std::string join_quoted(const std::vector<std::string>& items);
// " did you mean 'x'?" for the nearest accepted key, or the list of accepted keys.
std::string suggestion(const std::string& key, const std::vector<std::string>& accepted);
// The hint after "unknown key 'k'" in a plugin element: the nearest valid key, and, when the
// type describes its keys (`described`), every valid key, the core's and the plugin's.
std::string unknown_key_hint(const std::string& key, const std::vector<std::string>& valid, const std::string& type,
                             const std::string& kind, bool described);
Mat3 rotation_z(double angle);
bool valid_name(const std::string& name);
// Principal moments of inertia: >= 0, each at most the sum of the other two (Eq. 7.95).
void check_principal_moments(const Vec3& moments, const Param& where, const std::string& what,
                             const std::string& which);

// Line of every map key, recorded once the Param tree is final (addresses are stable).
using KeyLines = std::map<const Param*, std::map<std::string, int>>;

void index_key_lines(const YAML::Node& node, const Param& p, KeyLines& lines);

// ---------------------------------------------------------------- the loader

// The names of a list of elements that only grows, indexed as it grows: the first element of
// a name, as a search in order finds it. A search per new element (its name unique, its bodies
// found) was O(N) string compares, O(N^2) to load an N-link chain.
class NameIndex {
public:
    template <class Elements>
    int find(const Elements& list, const std::string& name) {
        for (; indexed_ < list.size(); ++indexed_) first_.emplace(list[indexed_].name, static_cast<int>(indexed_));
        const auto it = first_.find(name);
        return it == first_.end() ? -1 : it->second;
    }

private:
    std::unordered_map<std::string, int> first_;
    size_t indexed_ = 0;
};

class Loader {
public:
    // `sections`: the application's top-level keys accepted beside the physics' (SceneSection)
    Loader(std::string file, Registry& registry, std::vector<SceneSection> sections = {})
        : file_(std::move(file)), registry_(registry), sections_(std::move(sections)) {}

    Scene load(const std::string& text) {
        detail::SceneTreeReader reader;
        const YAML::Node root = reader.parse(text, file_);
        root_ = reader.with_base(reader.convert(root, file_), file_);
        base_files_ = reader.base_files();
        index_key_lines(root, root_, key_lines_);
        build();
        return take_scene();
    }
    // A scene already read into a Param tree (`base:` merged): its keys' lines are the
    // lines of their values.
    Model load_document(Param root) {
        root_ = std::move(root);
        build();
        return std::move(model_);
    }

private:
    // --- locations and key checks
    std::string where(const Param& p) const { return p.location(); }

    int key_line(const Param& map, const std::string& key) const {
        auto it = key_lines_.find(&map);
        if (it != key_lines_.end()) {
            auto k = it->second.find(key);
            if (k != it->second.end()) return k->second;
        }
        auto f = map.fields.find(key);
        return f != map.fields.end() ? f->second.line : map.line;
    }
    // The map's own file: a key inherited through `base:` is in the base file.
    std::string key_where(const Param& map, const std::string& key) const {
        return (map.file.empty() ? file_ : map.file) + ":" + std::to_string(key_line(map, key));
    }

    [[noreturn]] void unknown_key(const Param& map, const std::string& key, const std::string& what,
                                  const std::vector<std::string>& accepted,
                                  const std::string& extra = std::string()) const {
        std::string message = "unknown key " + quote(key) + " in " + what + "; " + suggestion(key, accepted);
        if (!extra.empty()) message += " " + extra;
        throw InputError(key_where(map, key), message);
    }

    void check_keys(const Param& map, const std::string& what, const std::vector<std::string>& accepted,
                    const std::map<std::string, std::string>& hints = {}) const {
        for (const auto& kv : map.fields) {
            if (std::find(accepted.begin(), accepted.end(), kv.first) != accepted.end()) continue;
            auto hint = hints.find(kv.first);
            if (hint != hints.end())
                throw InputError(key_where(map, kv.first),
                                 "key " + quote(kv.first) + " is not accepted in " + what + ": " + hint->second);
            unknown_key(map, kv.first, what, accepted);
        }
    }

    const Param* find(const Param& map, const std::string& key) const {
        auto it = map.fields.find(key);
        return it == map.fields.end() ? nullptr : &it->second;
    }
    const Param& require(const Param& map, const std::string& key, const std::string& what,
                         const std::string& hint) const {
        const Param* p = find(map, key);
        if (!p) throw InputError(where(map), what + " needs " + quote(key) + " (" + hint + ")");
        return *p;
    }

    // --- values
    double number(const Param& p, const std::string& key, const std::string& what) const {
        return p.as_number(key, what);
    }

    Eigen::VectorXd vector(const Param& p, const std::string& key, const std::string& what, int size,
                           const std::string& shape) const {
        if (!p.is_list())
            p.fail(what + ": " + quote(key) + " must be a list of " + std::to_string(size) + " numbers " + shape);
        if (static_cast<int>(p.items.size()) != size)
            p.fail(what + ": " + quote(key) + " must have " + std::to_string(size) + " numbers " + shape +
                   ", got " + std::to_string(p.items.size()));
        Eigen::VectorXd v(size);
        for (int k = 0; k < size; ++k) v[k] = number(p.items[k], key, what);
        return v;
    }

    // A point or direction: 2 numbers in a planar scene, 3 in a spatial one (z = 0 when planar).
    Vec3 space_vector(const Param& p, const std::string& key, const std::string& what) const {
        const bool planar = model_.dimension == Dimension::Planar;
        const Eigen::VectorXd v =
            vector(p, key, what, planar ? 2 : 3, planar ? "[x, y] in a planar scene" : "[x, y, z] in a spatial scene");
        return planar ? Vec3(v[0], v[1], 0.0) : Vec3(v[0], v[1], v[2]);
    }

    Mat3 matrix3(const Param& p, const std::string& key, const std::string& what) const {
        const std::string shape = "[[a11, a12, a13], [a21, a22, a23], [a31, a32, a33]]";
        if (!p.is_list() || p.items.size() != 3)
            p.fail(what + ": " + quote(key) + " must be a 3x3 matrix " + shape);
        Mat3 m;
        for (int r = 0; r < 3; ++r) {
            const Param& row = p.items[r];
            if (!row.is_list() || row.items.size() != 3)
                row.fail(what + ": row " + std::to_string(r + 1) + " of " + quote(key) + " must have 3 numbers (" +
                         shape + ")");
            for (int c = 0; c < 3; ++c) m(r, c) = number(row.items[c], key, what);
        }
        return m;
    }

    std::string name_of(const Param& element, const std::string& kind, const std::string& key = "name") const {
        const Param* p = find(element, key);
        if (!p) throw InputError(where(element), kind + " needs a 'name'");
        if (!p->is_scalar() || p->text.empty()) p->fail(kind + ": 'name' must be a single word");
        if (!valid_name(p->text))
            p->fail(kind + " name " + quote(p->text) +
                    " may only contain letters, digits, '_' and '-' (it becomes a CSV column prefix)");
        return p->text;
    }

    const Param& list_section(const std::string& key) const {
        const Param& p = root_.fields.at(key);
        if (!p.is_list())
            throw InputError(key_where(root_, key), quote(key) + " must be a list (items start with '- ')");
        return p;
    }

    std::vector<std::string> body_names() const {
        std::vector<std::string> names{"ground"};
        for (const auto& b : model_.bodies) names.push_back(b.name);
        return names;
    }

    int body_index(const Param& p, const std::string& what) const {
        if (!p.is_scalar() || p.text.empty()) p.fail(what + ": a body must be given by its name");
        if (p.text == "ground") return kGround;
        const int k = name_indexes_[&model_.bodies].find(model_.bodies, p.text);
        if (k >= 0) return k;
        p.fail(what + ": undefined body " + quote(p.text) + "; defined bodies are " + join_quoted(body_names()));
    }

    // What a force plugin is made from: the element's name, type, bodies, markers, the scene's
    // gravity and the element's keys.
    ForceSpec force_spec(const ForceInstance& force, const Params& params) const {
        ForceSpec spec;
        spec.name = force.name;
        spec.type = force.type;
        spec.dimension = model_.dimension;
        spec.bodies = element_body_infos(force.bodies, force.flexible);
        spec.markers = force.markers;
        spec.gravity = model_.gravity;
        spec.params = params;
        return spec;
    }

    BodyInfo body_info(int index) const {
        BodyInfo info;
        if (index == kGround) {
            info.name = "ground";
            info.ground = true;
            return info;
        }
        const Body& b = model_.bodies[index];
        info.name = b.name;
        info.mass = b.mass;
        info.inertia = b.inertia;
        info.position = b.position;
        info.orientation = initial_rotation(index);
        info.angle = b.angle;
        return info;
    }

    Mat3 initial_rotation(int index) const {
        if (index == kGround) return Mat3::Identity();
        const Body& b = model_.bodies[index];
        return model_.dimension == Dimension::Planar ? rotation_z(b.angle)
                                                     : rotation_from_euler_parameters(b.euler_parameters);
    }
    Vec3 initial_position(int index) const { return index == kGround ? Vec3::Zero() : model_.bodies[index].position; }

    // A world frame (origin, axes as columns) at t = 0 seen from a body: the marker.
    Marker marker_from_world(int body, const Vec3& origin, const Mat3& axes) const {
        return marker_in_frame(initial_position(body), initial_rotation(body),
                               body == kGround ? 0.0 : model_.bodies[body].angle, origin, axes);
    }
    // The same seen from a frame at `position` with axes A (planar: rotated by `angle`).
    Marker marker_in_frame(const Vec3& position, const Mat3& A, double angle, const Vec3& origin,
                           const Mat3& axes) const {
        Marker m;
        m.u_bar = A.transpose() * (origin - position);
        m.A_bar = A.transpose() * axes;
        if (model_.dimension == Dimension::Planar) {
            m.u_bar.z() = 0.0;
            m.angle = std::atan2(axes(1, 0), axes(0, 0)) - angle;
            m.A_bar = rotation_z(m.angle);
        }
        return m;
    }

    // --- the sections
    void build();
    // The top-level keys: the physics' and the declared application sections', each other one
    // refused at its file:line; the Model's document without the application sections.
    void check_top_level_keys();
    Scene take_scene();
    void load_formulation(const Param& node);
    void load_body(const Param& node, int index);
    // scene_flexible.cpp: `flexible_bodies:` and joints at their points
    void load_flexible_body(const Param& node, int index);
    std::vector<std::string> flexible_body_names() const;
    // One item of a joint's or force's `bodies`: a rigid body's name or ground (its index), or a
    // point of a flexible body, {body: NAME, node: K} or {body: NAME, at: xi}, added to
    // `flexible` at this slot (kGround returned: the slot is not a rigid body).
    int element_body(const Param& item, const std::string& what, int slot, std::vector<FlexibleAttachment>& flexible) const;
    // The material frame at an attachment in the initial configuration, as a body (ground = false).
    BodyInfo flexible_body_info(const FlexibleAttachment& at) const;
    // Refuses a joint at a flexible body that is driven or has velocity-level rows (not mapped yet).
    void check_flexible_joint(const JointInstance& joint) const;
    Mat3 body_inertia(const Param& inertia, const std::string& what) const;
    Vec4 body_orientation(const Param& orientation, const std::string& what) const;
    void load_joint(const Param& node, int index);
    void load_force(const Param& node, int index);
    std::vector<int> force_bodies(const Param& node, const std::string& what, std::vector<FlexibleAttachment>& flexible) const;
    // The markers' frames at t = 0: each slot's body, a flexible slot's material frame.
    std::vector<BodyInfo> element_body_infos(const std::vector<int>& bodies,
                                             const std::vector<FlexibleAttachment>& flexible) const;
    std::vector<Marker> force_markers(const Param& node, const std::string& what, const ForceInstance& force,
                                      Params& params) const;
    void load_driver(const Param& node, int index);
    void load_actuator(const Param& node, int index);
    void load_joint_limits(const Param& node, JointInstance& joint) const;
    void add_collision_contact();  // scene_collision.cpp
    // A second element of this kind with this name is refused at its 'name' key.
    template <class Elements>
    void require_unique_name(const Elements& existing, const std::string& name, const Param& node,
                             const std::string& kind) const {
        const int k = name_indexes_[&existing].find(existing, name);
        if (k >= 0)
            (find(node, "name") ? *find(node, "name") : node)
                .fail("duplicate " + kind + " name " + quote(name) + " (first defined at " + existing[k].where + "); " +
                      kind + " names must be unique");
    }
    // The common start of a list element of this kind: a map (of the keys `keys_hint` lists),
    // its name (required, or else KIND<index>), unique among the existing ones, and where it
    // is. Returns "KIND 'name'" for messages.
    template <class Element>
    std::string start_element(const Param& node, int index, const std::string& kind, const std::string& keys_hint,
                              bool name_required, const std::vector<Element>& existing, Element& element) const {
        const std::string fallback = kind + " #" + std::to_string(index + 1);
        if (!node.is_map()) node.fail(fallback + " must be a map of keys (" + keys_hint + ")");
        element.name = name_required || find(node, "name") ? name_of(node, fallback) : kind + std::to_string(index);
        element.where = where(node);
        require_unique_name(existing, element.name, node, kind);
        return kind + " " + quote(element.name);
    }
    // start_element() of an element whose name is optional and whose keys are exactly these.
    template <class Element>
    std::string open_element(const Param& node, int index, const std::string& kind,
                             const std::vector<std::string>& keys, const std::vector<Element>& existing,
                             Element& element) const {
        const std::string what = start_element(node, index, kind, join(keys), false, existing, element);
        check_keys(node, what, keys);
        return what;
    }
    // The joint a driver or actuator names (`joint` key), which must have one coordinate;
    // `purpose` ends the message when it has none ("to drive; drive a revolute, ...").
    int coordinate_joint(const Param& joint, const std::string& what, const std::string& purpose) const;
    int reaction_load_joint(const Param& node, const std::string& what, const ForceInstance& force) const;
    void check_stop_coordinate(const Param& node, const std::string& what, const ForceInstance& force) const;
    void add_gravity();

    // The joint-style frame of an element (point, axis, x_axis, axes), in world at t = 0.
    struct WorldFrame {
        Vec3 origin = Vec3::Zero();
        Mat3 axes = Mat3::Identity();
    };
    WorldFrame joint_frame(const Param& node, const std::string& what, const std::string& type,
                           const std::vector<int>& bodies, bool allow_axes) const;

    // Create a plugin element, then reject keys neither the core nor the plugin read.
    // `kind` and `type` find the type's key description (plugin_description.hpp), which tells
    // a key no type accepts from a documented key that is wrong where it stands.
    template <class Create>
    auto create_checked(const Params& params, const Param& node, const std::string& what, const std::string& kind,
                        const std::string& type, Create&& create) const;

    std::string file_;
    std::vector<std::string> base_files_;  // the `base:` files read
    Registry& registry_;
    std::vector<SceneSection> sections_;
    Param root_;
    KeyLines key_lines_;
    Model model_;
    // per list of the model (bodies, joints, drivers, actuators): its names (body_index, require_unique_name)
    mutable std::map<const void*, NameIndex> name_indexes_;
};

template <class Create>
auto Loader::create_checked(const Params& params, const Param& node, const std::string& what,
                            const std::string& kind, const std::string& type, Create&& create) const {
    // the keys the core read for the element, before the plugin reads its own
    const std::vector<std::string> core_keys(params.asked_keys().begin(), params.asked_keys().end());
    const PluginDescription* description = plugin_description(registry_, kind, type);
    // with a description the valid keys are known whatever the plugin read before it stopped;
    // without one (an older plugin), the keys it asked for
    auto valid_keys = [&] {
        std::vector<std::string> keys = core_keys;
        const std::vector<std::string> own =
            description ? key_names(*description)
                        : std::vector<std::string>(params.asked_keys().begin(), params.asked_keys().end());
        for (const std::string& k : own)
            if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
        return keys;
    };
    auto documented = [&](const std::string& key) { return description && description->find(key.c_str()); };
    auto unknown_note = [&]() -> std::string {
        const std::vector<std::string> valid = valid_keys();
        for (const auto& key : params.unread_keys()) {
            if (documented(key) || std::find(valid.begin(), valid.end(), key) != valid.end()) continue;
            const std::string hint = suggestion(key, valid);
            // without a description, only a likely misspelling (the plugin may have failed
            // before asking for the rest of its keys)
            if (description || hint.rfind("did you mean", 0) == 0)
                return "unknown key " + quote(key) + " at line " + std::to_string(key_line(node, key)) + ": " +
                       unknown_key_hint(key, valid, type, kind, description != nullptr);
        }
        return {};
    };
    try {
        auto element = create();
        const auto unread = params.unread_keys();
        if (!unread.empty()) {
            // report the first unread key in file order
            std::string first = unread.front();
            for (const auto& k : unread)
                if (key_line(node, k) < key_line(node, first)) first = k;
            if (documented(first))
                throw InputError(key_where(node, first),
                                 what + ": key " + quote(first) + " is a key of the " + kind + " type " + quote(type) +
                                     " but it has no effect with the other keys given here (" + first + ": " +
                                     description->find(first.c_str())->meaning + "); remove it or give the keys it goes with");
            throw InputError(key_where(node, first), "unknown key " + quote(first) + " in " + what + "; " +
                                                         unknown_key_hint(first, valid_keys(), type, kind,
                                                                          description != nullptr));
        }
        return element;
    } catch (const InputError& e) {
        const std::string note = unknown_note();
        if (note.empty() || e.message().find("unknown key") != std::string::npos) throw;
        rethrow_input_error(e, e.message() + " (note: " + note + ")");
    }
}

}  // namespace mbd::scene_detail
