// Scene loader: YAML -> mbd::Param tree -> Model (bodies, joints, forces,
// drivers). The format is documented in docs/scene-format.md.
//
// Every error is an InputError whose `where` is "file:line" and whose message
// names the element and says what to do. Unknown keys are rejected at the key's
// line with the nearest accepted key as a suggestion; for plugin elements the
// accepted keys are the core's keys plus the keys the plugin asked for.
#include <mbd/scene.hpp>
#include <mbd/sdk/suggest.hpp>
#include <mbd/visual.hpp>
#include <mbd/sdk/text.hpp>

#include "scene_source.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

namespace mbd {
namespace {

// ---------------------------------------------------------------- small helpers

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string join(const std::vector<std::string>& items, const std::string& sep = ", ") {
    std::string out;
    for (size_t k = 0; k < items.size(); ++k) {
        if (k) out += sep;
        out += items[k];
    }
    return out;
}

std::string join_quoted(const std::vector<std::string>& items) {
    std::vector<std::string> q;
    q.reserve(items.size());
    for (const auto& s : items) q.push_back(quote(s));
    return join(q);
}

// " did you mean 'x'?" for the nearest accepted key, or the list of accepted keys.
std::string suggestion(const std::string& key, const std::vector<std::string>& accepted) {
    const std::string best = nearest_name(key, accepted);
    if (!best.empty()) return "did you mean " + quote(best) + "?";
    if (accepted.empty()) return "remove it";
    return "accepted keys are " + join_quoted(accepted);
}

Mat3 rotation_z(double angle) {
    Mat3 a = Mat3::Identity();
    a.topLeftCorner<2, 2>() = planar_rotation(angle);
    return a;
}

bool valid_name(const std::string& name) {
    if (name.empty()) return false;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                        c == '_' || c == '-';
        if (!ok) return false;
    }
    return true;
}

// Principal moments of inertia of a rigid body about its mass centre (Shabana Eq. 7.95,
// J_xx = integral of (y^2 + z^2) dm, ...) are >= 0 and each is at most the sum of the
// other two: J_a + J_b - J_c = 2 integral of c^2 dm >= 0. Equality is a flat body (a disk:
// J_z = J_x + J_y), a rod has one zero moment; anything beyond is no rigid body. The
// relative tolerance admits moments computed or rounded at full precision on that boundary.
void check_principal_moments(const Vec3& moments, const Param& where, const std::string& what,
                             const std::string& which) {
    constexpr double tolerance = 1e-9;
    const double scale = moments.cwiseAbs().sum();
    const std::string listed =
        format_number(moments[0]) + ", " + format_number(moments[1]) + ", " + format_number(moments[2]);
    if (!(moments.minCoeff() >= -tolerance * scale))
        where.fail(what + ": 'inertia' is not positive semi-definite: " + which + " are " + listed +
                   "; a mass distribution has no negative moment");
    for (int c = 0; c < 3; ++c) {
        const double a = moments[(c + 1) % 3], b = moments[(c + 2) % 3];
        if (moments[c] > a + b + tolerance * scale)
            where.fail(what + ": 'inertia' is not a rigid body's: " + which + " are " + listed + ", and " +
                       format_number(moments[c]) + " exceeds the sum of the other two (" + format_number(a) + " + " + format_number(b) +
                       "); each principal moment must be at most the sum of the other two (equal for a flat "
                       "body), so check the values and that they are about the mass centre");
    }
}

// Line of every map key, recorded once the Param tree is final (addresses are stable).
using KeyLines = std::map<const Param*, std::map<std::string, int>>;

void index_key_lines(const YAML::Node& node, const Param& p, KeyLines& lines) {
    if (p.is_list() && node.IsSequence()) {
        size_t k = 0;
        for (const auto& item : node) {
            if (k >= p.items.size()) break;
            index_key_lines(item, p.items[k++], lines);
        }
    } else if (p.is_map() && node.IsMap()) {
        for (const auto& kv : node) {
            if (!kv.first.IsScalar()) continue;
            const std::string key = kv.first.Scalar();
            auto it = p.fields.find(key);
            if (it == p.fields.end()) continue;
            const YAML::Mark m = kv.first.Mark();
            lines[&p][key] = m.is_null() ? p.line : m.line + 1;
            index_key_lines(kv.second, it->second, lines);
        }
    }
}

// ---------------------------------------------------------------- the loader

class Loader {
public:
    Loader(std::string file, Registry& registry) : file_(std::move(file)), registry_(registry) {}

    Model load(const std::string& text) {
        detail::SceneTreeReader reader;
        const YAML::Node root = reader.parse(text, file_);
        root_ = reader.with_base(reader.convert(root, file_), file_);
        base_files_ = reader.base_files();
        index_key_lines(root, root_, key_lines_);
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
    std::string key_where(const Param& map, const std::string& key) const {
        return file_ + ":" + std::to_string(key_line(map, key));
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
        for (int k = 0; k < model_.body_count(); ++k)
            if (model_.bodies[k].name == p.text) return k;
        p.fail(what + ": undefined body " + quote(p.text) + "; defined bodies are " + join_quoted(body_names()));
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
        const Mat3 A = initial_rotation(body);
        Marker m;
        m.u_bar = A.transpose() * (origin - initial_position(body));
        m.A_bar = A.transpose() * axes;
        if (model_.dimension == Dimension::Planar) {
            m.u_bar.z() = 0.0;
            const double body_angle = body == kGround ? 0.0 : model_.bodies[body].angle;
            m.angle = std::atan2(axes(1, 0), axes(0, 0)) - body_angle;
            m.A_bar = rotation_z(m.angle);
        }
        return m;
    }

    // --- the sections
    void build();
    void load_formulation(const Param& node);
    void load_body(const Param& node, int index);
    void load_joint(const Param& node, int index);
    void load_force(const Param& node, int index);
    void load_driver(const Param& node, int index);
    void load_actuator(const Param& node, int index);
    void load_joint_limits(const Param& node, JointInstance& joint) const;
    void add_gravity();

    // The joint-style frame of an element (point, axis, x_axis, axes), in world at t = 0.
    struct WorldFrame {
        Vec3 origin = Vec3::Zero();
        Mat3 axes = Mat3::Identity();
    };
    WorldFrame joint_frame(const Param& node, const std::string& what, const std::string& type,
                           const std::vector<int>& bodies, bool allow_axes) const;

    // Create a plugin element, then reject keys neither the core nor the plugin read.
    template <class Create>
    auto create_checked(const Params& params, const Param& node, const std::string& what, Create&& create) const;

    std::string file_;
    std::vector<std::string> base_files_;  // the `base:` files read
    Registry& registry_;
    Param root_;
    KeyLines key_lines_;
    Model model_;
};

// ---------------------------------------------------------------- top level

void Loader::build() {
    if (root_.is_scalar() && root_.text.empty())
        throw InputError(file_ + ":1", "the scene is empty; it needs at least 'dimension' and 'bodies'");
    if (!root_.is_map())
        root_.fail("a scene must be a map of keys (name, dimension, gravity, bodies, joints, forces, drivers)");

    check_keys(root_, "scene",
               {"name", "dimension", "gravity", "bodies", "joints", "forces", "drivers", "formulation", "actuators",
                "bench", "expect"});  // bench: read by `mbd bench` (app/src/bench.cpp) from Model::document;
                                      // expect: stored raw for `mbd stability` (app/src/stability.cpp)

    model_.source = file_;
    model_.base_files = base_files_;
    model_.document = std::make_shared<const Param>(root_);
    if (const Param* name = find(root_, "name")) {
        if (!name->is_scalar()) name->fail("scene: 'name' must be a single line of text");
        model_.name = name->text;
    } else {
        model_.name = std::filesystem::path(file_).stem().string();
    }

    const Param& dimension = require(root_, "dimension", "the scene", "planar or spatial");
    if (dimension.is_scalar() && dimension.text == "planar")
        model_.dimension = Dimension::Planar;
    else if (dimension.is_scalar() && dimension.text == "spatial")
        model_.dimension = Dimension::Spatial;
    else
        dimension.fail("scene: 'dimension' must be 'planar' or 'spatial', got " +
                       quote(dimension.is_scalar() ? dimension.text : std::string("a list or map")));

    if (const Param* g = find(root_, "gravity")) model_.gravity = space_vector(*g, "gravity", "scene");
    if (const Param* f = find(root_, "formulation")) load_formulation(*f);
    if (const Param* e = find(root_, "expect")) model_.expect_node = std::make_shared<Param>(*e);

    if (!find(root_, "bodies"))
        throw InputError(where(root_), "the scene needs 'bodies' (a list of at least one body)");
    const Param& bodies = list_section("bodies");
    if (bodies.items.empty())
        throw InputError(key_where(root_, "bodies"), "'bodies' is empty; define at least one body");
    for (size_t k = 0; k < bodies.items.size(); ++k) load_body(bodies.items[k], static_cast<int>(k));

    if (find(root_, "joints")) {
        const Param& joints = list_section("joints");
        for (size_t k = 0; k < joints.items.size(); ++k) load_joint(joints.items[k], static_cast<int>(k));
    }
    if (!model_.gravity.isZero(0.0)) add_gravity();
    if (find(root_, "forces")) {
        const Param& forces = list_section("forces");
        for (size_t k = 0; k < forces.items.size(); ++k) load_force(forces.items[k], static_cast<int>(k));
    }
    if (find(root_, "drivers")) {
        const Param& drivers = list_section("drivers");
        for (size_t k = 0; k < drivers.items.size(); ++k) load_driver(drivers.items[k], static_cast<int>(k));
    }
    if (find(root_, "actuators")) {
        const Param& actuators = list_section("actuators");
        for (size_t k = 0; k < actuators.items.size(); ++k) load_actuator(actuators.items[k], static_cast<int>(k));
    }
}

// ---------------------------------------------------------------- formulation

// `formulation: NAME` or `formulation: {type: NAME, ...keys of that formulation}`.
// The plugin reads (and checks) its own keys when the analysis creates it.
void Loader::load_formulation(const Param& node) {
    const Param* type = &node;
    if (node.is_map()) {
        type = find(node, "type");
        if (!type) node.fail("scene: 'formulation' needs a 'type' (for example augmented)");
    }
    if (!type->is_scalar() || type->text.empty())
        type->fail("scene: 'formulation' must name a formulation (for example augmented)");
    model_.formulation = type->text;
    model_.formulation_node = std::make_shared<Param>(node);
    model_.formulation_where = where(node);
}

// ---------------------------------------------------------------- bodies

void Loader::load_body(const Param& node, int index) {
    const std::string fallback = "body #" + std::to_string(index + 1);
    if (!node.is_map()) node.fail(fallback + " must be a map of keys (name, mass, inertia, position, ...)");
    const bool planar = model_.dimension == Dimension::Planar;

    Body body;
    body.name = name_of(node, fallback);
    const std::string what = "body " + quote(body.name);
    body.where = where(node);

    if (planar)
        check_keys(node, what, {"name", "mass", "inertia", "position", "angle", "velocity", "angular_velocity", "visual"},
                   {{"orientation", "planar bodies take 'angle' (radians), not 'orientation'"}});
    else
        check_keys(node, what,
                   {"name", "mass", "inertia", "position", "orientation", "velocity", "angular_velocity", "visual"},
                   {{"angle", "spatial bodies take 'orientation' ({euler_parameters: [..]}, {axis: [..], angle: ..} "
                              "or {matrix: [[..], [..], [..]]}), not 'angle'"}});

    if (body.name == "ground")
        find(node, "name")->fail("'ground' is reserved for the fixed ground; give the body another name");
    for (const auto& other : model_.bodies)
        if (other.name == body.name)
            find(node, "name")->fail("duplicate body name " + quote(body.name) + " (first defined at " + other.where +
                                     "); body names must be unique");

    // zero mass and inertia are accepted: kinematics and statics do not need them; dynamics
    // refuses a singular mass matrix by name (core/src/simulation.cpp)
    const Param& mass = require(node, "mass", what, "a positive number, kg");
    body.mass = number(mass, "mass", what);
    if (!(body.mass >= 0)) mass.fail(what + ": 'mass' must be positive (or 0 for a massless body), got " + mass.text);

    const Param& inertia = require(node, "inertia", what,
                                   planar ? "a positive number, kg m^2 about the mass centre"
                                          : "[Ixx, Iyy, Izz] or a 3x3 matrix about the mass centre, body axes");
    if (planar) {
        const double J = number(inertia, "inertia", what);
        if (!(J >= 0)) inertia.fail(what + ": 'inertia' must be positive (or 0), got " + inertia.text);
        body.inertia(2, 2) = J;
    } else {
        if (inertia.is_list() && !inertia.items.empty() && inertia.items[0].is_list()) {
            const Mat3 J = matrix3(inertia, "inertia", what);
            if (!J.isApprox(J.transpose(), 1e-9) && (J - J.transpose()).cwiseAbs().maxCoeff() > 1e-12)
                inertia.fail(what + ": 'inertia' matrix must be symmetric");
            const Mat3 Js = 0.5 * (J + J.transpose());
            const Eigen::SelfAdjointEigenSolver<Mat3> eig(Js);
            check_principal_moments(eig.eigenvalues(), inertia, what, "the principal moments (eigenvalues)");
            body.inertia = Js;
        } else {
            const Eigen::VectorXd d =
                vector(inertia, "inertia", what, 3, "[Ixx, Iyy, Izz] (or a 3x3 matrix)");
            for (int k = 0; k < 3; ++k)
                if (!(d[k] >= 0))
                    inertia.items[k].fail(what + ": 'inertia' moments must be positive (or 0), got " +
                                          inertia.items[k].text);
            check_principal_moments(d, inertia, what, "the principal moments [Ixx, Iyy, Izz]");
            body.inertia = d.asDiagonal();
        }
    }

    if (const Param* p = find(node, "position")) body.position = space_vector(*p, "position", what);
    if (const Param* v = find(node, "visual")) body.visuals = parse_visual(*v, model_.dimension, what);
    if (const Param* v = find(node, "velocity")) body.velocity = space_vector(*v, "velocity", what);

    if (planar) {
        if (const Param* a = find(node, "angle")) body.angle = number(*a, "angle", what);
        if (const Param* w = find(node, "angular_velocity"))
            body.angular_velocity = Vec3(0, 0, number(*w, "angular_velocity", what));
    } else {
        if (const Param* w = find(node, "angular_velocity"))
            body.angular_velocity = vector(*w, "angular_velocity", what, 3, "[wx, wy, wz] in world axes");
        if (const Param* o = find(node, "orientation")) {
            const std::string owhat = what + " orientation";
            if (!o->is_map())
                o->fail(what + ": 'orientation' must be one of {euler_parameters: [e0, e1, e2, e3]}, "
                               "{axis: [x, y, z], angle: radians} or {matrix: [[..], [..], [..]]}");
            const bool has_ep = find(*o, "euler_parameters"), has_axis = find(*o, "axis"),
                       has_angle = find(*o, "angle"), has_matrix = find(*o, "matrix");
            check_keys(*o, what + " 'orientation'", {"euler_parameters", "axis", "angle", "matrix"});
            const int forms = int(has_ep) + int(has_axis || has_angle) + int(has_matrix);
            if (forms != 1)
                o->fail(what + ": 'orientation' takes exactly one of 'euler_parameters', 'axis' + 'angle' or 'matrix'");
            if (has_ep) {
                const Param& e = *find(*o, "euler_parameters");
                Vec4 p = vector(e, "euler_parameters", what, 4, "[e0, e1, e2, e3]");
                if (!(p.norm() > 1e-12)) e.fail(what + ": 'euler_parameters' must not be all zero");
                body.euler_parameters = p / p.norm();
            } else if (has_matrix) {
                const Param& mp = *find(*o, "matrix");
                const Mat3 A = matrix3(mp, "matrix", what);
                if ((A.transpose() * A - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6 || A.determinant() < 0)
                    mp.fail(what + ": orientation 'matrix' must be a rotation matrix (orthonormal, determinant +1, "
                                   "within 1e-6)");
                body.euler_parameters = euler_parameters_from_rotation(A);
            } else {
                if (!has_axis) o->fail(what + ": 'orientation' with 'angle' also needs 'axis: [x, y, z]'");
                if (!has_angle) o->fail(what + ": 'orientation' with 'axis' also needs 'angle' (radians)");
                const Param& ap = *find(*o, "axis");
                const Vec3 axis = vector(ap, "axis", what, 3, "[x, y, z]");
                if (!(axis.norm() > 1e-12)) ap.fail(what + ": orientation 'axis' must not be the zero vector");
                const double angle = number(*find(*o, "angle"), "angle", what);
                body.euler_parameters = euler_parameters_from_axis_angle(axis, angle);
            }
        }
    }
    model_.bodies.push_back(std::move(body));
}

// ---------------------------------------------------------------- joint frames

Loader::WorldFrame Loader::joint_frame(const Param& node, const std::string& what, const std::string& type,
                                       const std::vector<int>& bodies, bool allow_axes) const {
    WorldFrame frame;
    // origin: the given point, else the first non-ground body's initial mass centre
    if (const Param* p = find(node, "point")) {
        frame.origin = space_vector(*p, "point", what);
    } else {
        for (int b : bodies)
            if (b != kGround) {
                frame.origin = model_.bodies[b].position;
                break;
            }
    }

    if (model_.dimension == Dimension::Planar) {
        if (const Param* a = find(node, "axis")) {
            const Vec3 axis = space_vector(*a, "axis", what);
            if (!(axis.norm() > 1e-12)) a->fail(what + ": 'axis' must not be the zero vector");
            frame.axes = rotation_z(std::atan2(axis.y(), axis.x()));
        }
        return frame;
    }

    const Param* axes = allow_axes ? find(node, "axes") : nullptr;
    const Param* axis = find(node, "axis");
    const Param* x_axis = find(node, "x_axis");
    if (axes) {
        if (axis || x_axis)
            axes->fail(what + ": give either 'axes: [a1, a2]' or 'axis' (and 'x_axis'), not both");
        if (!axes->is_list() || axes->items.size() != 2)
            axes->fail(what + ": 'axes' must be a list of two directions [[x, y, z], [x, y, z]]");
        const Vec3 a1 = space_vector(axes->items[0], "axes", what);
        const Vec3 a2 = space_vector(axes->items[1], "axes", what);
        if (!(a1.norm() > 1e-12)) axes->items[0].fail(what + ": the first of 'axes' must not be the zero vector");
        if (!(a2.norm() > 1e-12)) axes->items[1].fail(what + ": the second of 'axes' must not be the zero vector");
        const Vec3 z = a1.normalized();
        Vec3 x = a2.normalized();
        if (std::abs(z.dot(x)) > 1e-6)
            axes->fail(what + ": the two 'axes' must be perpendicular (their unit vectors' dot product is " +
                       format_number(z.dot(x)) + ")");
        x = (x - x.dot(z) * z).normalized();
        frame.axes.col(0) = x;
        frame.axes.col(1) = z.cross(x);
        frame.axes.col(2) = z;
        return frame;
    }
    if (type == "universal" && allow_axes)
        node.fail(what + ": a universal joint needs 'axes: [a1, a2]', the two perpendicular cross-bar axes in world "
                         "(a1 fixed on the first body, a2 on the second)");

    Vec3 z = Vec3::UnitZ();
    if (axis) {
        z = space_vector(*axis, "axis", what);
        if (!(z.norm() > 1e-12)) axis->fail(what + ": 'axis' must not be the zero vector; give a direction [x, y, z]");
        z.normalize();
    }
    Vec3 x;
    if (x_axis) {
        x = space_vector(*x_axis, "x_axis", what);
        if (!(x.norm() > 1e-12)) x_axis->fail(what + ": 'x_axis' must not be the zero vector");
        x.normalize();
        x = x - x.dot(z) * z;
        if (!(x.norm() > 1e-6))
            x_axis->fail(what + ": 'x_axis' must not be parallel to 'axis'; give a direction across the axis");
        x.normalize();
    } else {
        x = any_perpendicular(z);
    }
    frame.axes.col(0) = x;
    frame.axes.col(1) = z.cross(x);
    frame.axes.col(2) = z;
    return frame;
}

template <class Create>
auto Loader::create_checked(const Params& params, const Param& node, const std::string& what, Create&& create) const {
    auto unknown_note = [&]() -> std::string {
        const auto unread = params.unread_keys();
        if (unread.empty()) return {};
        // only when an unread key looks like a misspelling of a key that was asked for
        // (the plugin may have failed before asking for the rest)
        const std::vector<std::string> accepted(params.asked_keys().begin(), params.asked_keys().end());
        for (const auto& key : unread) {
            const std::string hint = suggestion(key, accepted);
            if (hint.rfind("did you mean", 0) == 0)
                return "unknown key " + quote(key) + " at line " + std::to_string(key_line(node, key)) + ": " + hint;
        }
        return {};
    };
    try {
        auto element = create();
        const auto unread = params.unread_keys();
        if (!unread.empty()) {
            const std::vector<std::string> accepted(params.asked_keys().begin(), params.asked_keys().end());
            // report the first unknown key in file order
            std::string first = unread.front();
            for (const auto& k : unread)
                if (key_line(node, k) < key_line(node, first)) first = k;
            unknown_key(node, first, what, accepted);
        }
        return element;
    } catch (const InputError& e) {
        const std::string note = unknown_note();
        if (note.empty() || e.message().find("unknown key") != std::string::npos) throw;
        throw InputError(e.where(), e.message() + " (note: " + note + ")");
    }
}

// ---------------------------------------------------------------- joints

void Loader::load_joint(const Param& node, int index) {
    const std::string fallback = "joint #" + std::to_string(index + 1);
    if (!node.is_map()) node.fail(fallback + " must be a map of keys (name, type, bodies, point, ...)");
    const bool planar = model_.dimension == Dimension::Planar;

    JointInstance joint;
    joint.name = name_of(node, fallback);
    const std::string what = "joint " + quote(joint.name);
    joint.where = where(node);
    for (const auto& other : model_.joints)
        if (other.name == joint.name)
            find(node, "name")->fail("duplicate joint name " + quote(joint.name) + " (first defined at " +
                                     other.where + "); joint names must be unique");

    const Param& type = require(node, "type", what, "the joint type, e.g. revolute");
    if (!type.is_scalar() || type.text.empty()) type.fail(what + ": 'type' must be a single word, e.g. revolute");
    joint.type = type.text;

    const Param& bodies = require(node, "bodies", what, "[body_a, body_b], names of bodies or 'ground'");
    if (!bodies.is_list() || bodies.items.size() < 2 || bodies.items.size() > 3)
        bodies.fail(what + ": 'bodies' must list two body names [a, b] (a third for a carrier), got " +
                    (bodies.is_list() ? std::to_string(bodies.items.size()) + " items" : std::string("no list")));
    for (const auto& item : bodies.items) joint.bodies.push_back(body_index(item, what));
    for (size_t a = 0; a < joint.bodies.size(); ++a)
        for (size_t b = a + 1; b < joint.bodies.size(); ++b)
            if (joint.bodies[a] == joint.bodies[b])
                bodies.fail(what + ": body " + quote(bodies.items[a].text) +
                            " appears twice in 'bodies'; a joint connects different bodies");

    Params params(what, &node);
    std::vector<std::string> core_keys{"name", "type", "bodies", "point", "axis", "limits"};
    if (!planar) {
        core_keys.push_back("x_axis");
        core_keys.push_back("axes");
    }
    for (const auto& k : core_keys) params.mark_read(k);

    const WorldFrame frame = joint_frame(node, what, joint.type, joint.bodies, true);

    JointSpec spec;
    spec.name = joint.name;
    spec.type = joint.type;
    spec.dimension = model_.dimension;
    for (int b : joint.bodies) {
        spec.bodies.push_back(body_info(b));
        joint.markers.push_back(marker_from_world(b, frame.origin, frame.axes));
    }
    spec.markers = joint.markers;
    spec.params = params;

    const std::string at = key_where(node, "type");
    joint.joint = create_checked(params, node, what, [&] { return registry_.create_joint(spec, at); });
    if (!joint.joint) type.fail(what + ": the plugin for type " + quote(joint.type) + " created no joint");
    load_joint_limits(node, joint);
    model_.joints.push_back(std::move(joint));
}

// ---------------------------------------------------------------- forces

void Loader::add_gravity() {
    ForceInstance force;
    force.name = "gravity";
    force.type = "gravity";
    force.where = key_where(root_, "gravity");
    ForceSpec spec;
    spec.name = force.name;
    spec.type = force.type;
    spec.dimension = model_.dimension;
    spec.gravity = model_.gravity;
    for (int b = 0; b < model_.body_count(); ++b) {
        force.bodies.push_back(b);
        force.markers.emplace_back();
        spec.bodies.push_back(body_info(b));
    }
    spec.markers = force.markers;
    spec.params = Params("force 'gravity'", nullptr);
    force.force = registry_.create_force(spec, force.where);
    model_.forces.push_back(std::move(force));
}

void Loader::load_force(const Param& node, int index) {
    const std::string fallback = "force #" + std::to_string(index + 1);
    if (!node.is_map()) node.fail(fallback + " must be a map of keys (type, body or bodies, ...)");

    const Param& type = require(node, "type", fallback, "the force type, e.g. spring_damper");
    if (!type.is_scalar() || type.text.empty()) type.fail(fallback + ": 'type' must be a single word");

    ForceInstance force;
    force.type = type.text;
    force.name = find(node, "name") ? name_of(node, fallback) : force.type + std::to_string(index);
    const std::string what = "force " + quote(force.name);
    force.where = where(node);
    if (force.type == "gravity")
        type.fail(what + ": gravity is not listed under 'forces'; set the top-level 'gravity: [gx, gy" +
                  std::string(model_.dimension == Dimension::Spatial ? ", gz" : "") + "]' instead");
    for (const auto& other : model_.forces)
        if (other.name == force.name)
            (find(node, "name") ? *find(node, "name") : node)
                .fail("duplicate force name " + quote(force.name) + " (first defined at " + other.where +
                      "); force names must be unique");

    const Param* body = find(node, "body");
    const Param* bodies = find(node, "bodies");
    if (body && bodies) body->fail(what + ": give either 'body: NAME' or 'bodies: [a, b]', not both");
    if (!body && !bodies)
        throw InputError(where(node), what + " needs 'body: NAME' (one body) or 'bodies: [a, b]' (two bodies)");
    if (body) {
        force.bodies.push_back(body_index(*body, what));
    } else {
        if (!bodies->is_list() || bodies->items.empty())
            bodies->fail(what + ": 'bodies' must be a list of body names [a, b]");
        for (const auto& item : bodies->items) force.bodies.push_back(body_index(item, what));
    }
    const Param& body_list = body ? *body : *bodies;
    if (force.bodies.size() == 1 && force.bodies[0] == kGround)
        body_list.fail(what + ": a force on the ground alone has no effect; apply it to a moving body");
    for (size_t a = 0; a < force.bodies.size(); ++a)
        for (size_t b = a + 1; b < force.bodies.size(); ++b)
            if (force.bodies[a] == force.bodies[b])
                body_list.fail(what + ": a body appears twice in 'bodies'; a force connects different bodies");

    const bool planar = model_.dimension == Dimension::Planar;
    const bool single = force.bodies.size() == 1;
    Params params(what, &node);
    for (const auto& k : {"name", "type", "body", "bodies", "point", "points"}) params.mark_read(k);

    const Param* point = find(node, "point");
    const Param* points = find(node, "points");
    const Param* axis = find(node, "axis");
    const Param* x_axis = find(node, "x_axis");
    if (point && points) point->fail(what + ": give either 'point' or 'points', not both");

    if (single) {
        // one body: `point` in the body's own frame (default: the mass centre)
        if (points) {
            if (!points->is_list() || points->items.size() != 1)
                points->fail(what + ": 'points' must list one point per body (1 here); or use 'point: [..]'");
            point = &points->items[0];
        }
        Marker m;
        if (point) m.u_bar = space_vector(*point, "point", what);
        force.markers.push_back(m);
    } else if (points) {
        // one point per body, each in that body's own frame, body-aligned axes
        if (!points->is_list() || points->items.size() != force.bodies.size())
            points->fail(what + ": 'points' must list one point per body (" + std::to_string(force.bodies.size()) +
                         "), each in that body's own frame");
        for (const auto& p : points->items) {
            Marker m;
            m.u_bar = space_vector(p, "points", what);
            force.markers.push_back(m);
        }
        if (axis || x_axis)
            (axis ? axis : x_axis)
                ->fail(what + ": 'axis' / 'x_axis' go with a world 'point' (a joint-like frame), not with 'points'");
    } else if (point || axis) {
        // a joint-like frame in world at t = 0: markers coincide at the point
        params.mark_read("axis");
        if (!planar) params.mark_read("x_axis");
        const WorldFrame frame = joint_frame(node, what, force.type, force.bodies, false);
        for (int b : force.bodies) force.markers.push_back(marker_from_world(b, frame.origin, frame.axes));
    } else {
        // default: each body's mass centre, body-aligned axes
        for (size_t k = 0; k < force.bodies.size(); ++k) force.markers.emplace_back();
    }

    ForceSpec spec;
    spec.name = force.name;
    spec.type = force.type;
    spec.dimension = model_.dimension;
    for (int b : force.bodies) spec.bodies.push_back(body_info(b));
    spec.markers = force.markers;
    spec.gravity = model_.gravity;
    spec.params = params;

    const std::string at = key_where(node, "type");
    force.force = create_checked(params, node, what, [&] { return registry_.create_force(spec, at); });
    if (!force.force) type.fail(what + ": the plugin for type " + quote(force.type) + " created no force");
    model_.forces.push_back(std::move(force));
}

// ---------------------------------------------------------------- drivers

void Loader::load_driver(const Param& node, int index) {
    const std::string fallback = "driver #" + std::to_string(index + 1);
    if (!node.is_map()) node.fail(fallback + " must be a map of keys (name, joint, motion)");

    Driver driver;
    driver.name = find(node, "name") ? name_of(node, fallback) : "driver" + std::to_string(index);
    const std::string what = "driver " + quote(driver.name);
    driver.where = where(node);
    check_keys(node, what, {"name", "joint", "motion"});
    for (const auto& other : model_.drivers)
        if (other.name == driver.name)
            (find(node, "name") ? *find(node, "name") : node)
                .fail("duplicate driver name " + quote(driver.name) + " (first defined at " + other.where +
                      "); driver names must be unique");

    const Param& joint = require(node, "joint", what, "the name of the joint whose coordinate it prescribes");
    if (!joint.is_scalar() || joint.text.empty()) joint.fail(what + ": 'joint' must be a joint name");
    for (int k = 0; k < static_cast<int>(model_.joints.size()); ++k)
        if (model_.joints[k].name == joint.text) driver.joint = k;
    if (driver.joint < 0) {
        std::vector<std::string> names;
        for (const auto& j : model_.joints) names.push_back(j.name);
        joint.fail(what + ": undefined joint " + quote(joint.text) + "; defined joints are " +
                   (names.empty() ? std::string("(none)") : join_quoted(names)));
    }
    const JointInstance& target = model_.joints[driver.joint];
    if (!target.joint->has_coordinate())
        joint.fail(what + ": joint " + quote(target.name) + " (" + target.type +
                   ") has no single coordinate to drive; drive a revolute, prismatic or other 1-DOF joint");
    for (const auto& other : model_.drivers)
        if (other.joint == driver.joint)
            joint.fail(what + ": joint " + quote(target.name) + " is already driven by driver " + quote(other.name) +
                       "; a joint takes one driver");

    const Param& motion = require(node, "motion", what, "a time function, e.g. {type: linear, initial: 0, rate: 1}");
    driver.motion = make_time_function(motion, what);
    model_.drivers.push_back(std::move(driver));
}

// ---------------------------------------------------------------- limits, actuators

// `limits: [lo, hi]` on a 1-DOF joint's coordinate (statics turns them into bounds).
void Loader::load_joint_limits(const Param& node, JointInstance& joint) const {
    const Param* limits = find(node, "limits");
    if (!limits) return;
    const std::string what = "joint " + quote(joint.name);
    if (!joint.joint->has_coordinate())
        limits->fail(what + " (" + joint.type +
                     ") has no single coordinate to limit; 'limits' go on revolute, prismatic or other 1-DOF joints");
    const Eigen::VectorXd v = vector(*limits, "limits", what, 2, "[lo, hi] on the joint coordinate");
    if (!(v[0] <= v[1]))
        limits->fail(what + ": 'limits' [" + limits->items[0].text + ", " + limits->items[1].text +
                     "] are infeasible: lo must not exceed hi");
    joint.has_limits = true;
    joint.limit_lo = v[0];
    joint.limit_hi = v[1];
    joint.limits_where = where(*limits);
}

// An actuator: {name, joint, bounds: [lo, hi], weight} acting along the joint's coordinate.
void Loader::load_actuator(const Param& node, int index) {
    const std::string fallback = "actuator #" + std::to_string(index + 1);
    if (!node.is_map()) node.fail(fallback + " must be a map of keys (name, joint, bounds, weight)");
    Actuator actuator;
    actuator.name = find(node, "name") ? name_of(node, fallback) : "actuator" + std::to_string(index);
    const std::string what = "actuator " + quote(actuator.name);
    actuator.where = where(node);
    check_keys(node, what, {"name", "joint", "bounds", "weight"});
    for (const auto& other : model_.actuators)
        if (other.name == actuator.name)
            (find(node, "name") ? *find(node, "name") : node)
                .fail("duplicate actuator name " + quote(actuator.name) + " (first defined at " + other.where +
                      "); actuator names must be unique");
    const Param& joint = require(node, "joint", what, "the name of the joint along whose coordinate it acts");
    if (!joint.is_scalar() || joint.text.empty()) joint.fail(what + ": 'joint' must be a joint name");
    for (int k = 0; k < static_cast<int>(model_.joints.size()); ++k)
        if (model_.joints[k].name == joint.text) actuator.joint = k;
    if (actuator.joint < 0) {
        std::vector<std::string> names;
        for (const auto& j : model_.joints) names.push_back(j.name);
        joint.fail(what + ": unknown joint " + quote(joint.text) + "; defined joints are " +
                   (names.empty() ? std::string("(none)") : join_quoted(names)));
    }
    const JointInstance& target = model_.joints[actuator.joint];
    if (!target.joint->has_coordinate())
        joint.fail(what + ": joint " + quote(target.name) + " (" + target.type +
                   ") has no single coordinate to act along; use a revolute, prismatic or other 1-DOF joint");
    if (const Param* bounds = find(node, "bounds")) {
        const Eigen::VectorXd v = vector(*bounds, "bounds", what, 2, "[lo, hi] on the effort");
        if (!(v[0] <= v[1]))
            bounds->fail(what + ": 'bounds' [" + bounds->items[0].text + ", " + bounds->items[1].text +
                         "] are infeasible: lo must not exceed hi");
        actuator.lo = v[0];
        actuator.hi = v[1];
    }
    if (const Param* weight = find(node, "weight")) {
        actuator.weight = number(*weight, "weight", what);
        if (!(actuator.weight > 0)) weight->fail(what + ": 'weight' must be positive, got " + weight->text);
    }
    model_.actuators.push_back(std::move(actuator));
}

}  // namespace

Model load_scene_text(const std::string& yaml, const std::string& label, Registry& registry) {
    Loader loader(label, registry);
    return loader.load(yaml);
}

Model load_scene(const std::filesystem::path& file, Registry& registry) {
    return load_scene_text(detail::read_scene_file(file), file.string(), registry);
}

}  // namespace mbd
