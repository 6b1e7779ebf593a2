// Scene loader: YAML -> mbd::Param tree -> Model (bodies, joints, forces,
// drivers). The format is documented in docs/scene-format.md.
//
// Every error is an InputError whose `where` is "file:line" and whose message
// names the element and says what to do. Unknown keys are rejected at the key's
// line with the nearest accepted key as a suggestion; for plugin elements the
// accepted keys are the core's keys plus the keys the plugin asked for.
#include "scene/scene_loader.hpp"

#include "evaluation/beam_slider.hpp"

#include <mbd/formulation_setup.hpp>

#include <mutex>

namespace mbd {
namespace scene_detail {

// ---------------------------------------------------------------- small helpers

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string join(const std::vector<std::string>& items, const std::string& sep) {
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

std::string unknown_key_hint(const std::string& key, const std::vector<std::string>& valid, const std::string& type,
                             const std::string& kind, bool described) {
    if (!described) return suggestion(key, valid);
    const std::string best = nearest_name(key, valid);
    return (best.empty() ? std::string() : "did you mean " + quote(best) + "? ") + "the keys of a " + kind + " of type " +
           quote(type) + " are " + join_quoted(valid) + " (mbd plugins --keys " + type + ")";
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

// ---------------------------------------------------------------- top level

void Loader::check_top_level_keys() {
    std::vector<std::string> accepted = {"name",   "dimension", "gravity",     "ground",   "bodies", "flexible_bodies",
                                         "joints", "forces",    "drivers",     "formulation", "actuators"};
    const size_t physics = accepted.size();
    for (const SceneSection& section : sections_)
        if (std::find(accepted.begin(), accepted.end(), section.key) == accepted.end()) accepted.push_back(section.key);
    for (const auto& kv : root_.fields) {
        if (std::find(accepted.begin(), accepted.end(), kv.first) != accepted.end()) continue;
        // a misspelt application key: say whose it is
        std::string whose;
        const std::string best = nearest_name(kv.first, accepted);
        for (const SceneSection& section : sections_)
            if (section.key == best && !section.reader.empty()) whose = "('" + best + "' is read by " + section.reader + ")";
        unknown_key(root_, kv.first, "scene", accepted, whose);
    }
    // the physics alone for the Model (a parameter study loads it again without the application)
    Param physics_document = root_;
    for (size_t k = physics; k < accepted.size(); ++k) physics_document.fields.erase(accepted[k]);
    model_.document = std::make_shared<const Param>(std::move(physics_document));
}

Scene Loader::take_scene() {
    Scene scene;
    for (const SceneSection& section : sections_) {
        const auto it = root_.fields.find(section.key);
        if (it != root_.fields.end()) scene.sections.emplace(section.key, it->second);
    }
    scene.document = std::make_shared<const Param>(std::move(root_));
    scene.model = std::move(model_);
    return scene;
}

void Loader::build() {
    name_indexes_.clear();  // a fresh model: no names indexed
    if (root_.is_scalar() && root_.text.empty())
        throw InputError(file_ + ":1", "the scene is empty; it needs at least 'dimension' and 'bodies'");
    if (!root_.is_map())
        root_.fail("a scene must be a map of keys (name, dimension, gravity, bodies, joints, forces, drivers)");

    check_top_level_keys();
    model_.source = file_;
    model_.base_files = base_files_;
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

    const bool flexible = find(root_, "flexible_bodies") != nullptr;
    if (!find(root_, "bodies") && !flexible)
        throw InputError(where(root_), "the scene needs 'bodies' (a list of at least one body)");
    if (find(root_, "bodies")) {
        const Param& bodies = list_section("bodies");
        if (bodies.items.empty() && !flexible)
            throw InputError(key_where(root_, "bodies"), "'bodies' is empty; define at least one body");
        for (size_t k = 0; k < bodies.items.size(); ++k) load_body(bodies.items[k], static_cast<int>(k));
    }
    if (flexible) {  // after every rigid body: their coordinates follow the rigid ones' (model.hpp)
        const Param& bodies = list_section("flexible_bodies");
        for (size_t k = 0; k < bodies.items.size(); ++k) load_flexible_body(bodies.items[k], static_cast<int>(k));
    }

    if (find(root_, "joints")) {
        const Param& joints = list_section("joints");
        for (size_t k = 0; k < joints.items.size(); ++k) load_joint(joints.items[k], static_cast<int>(k));
    }
    if (!model_.gravity.isZero(0.0) && model_.body_count() > 0) add_gravity();  // flexible bodies add their own
    if (find(root_, "forces")) {
        const Param& forces = list_section("forces");
        for (size_t k = 0; k < forces.items.size(); ++k) load_force(forces.items[k], static_cast<int>(k));
    }
    add_collision_contact();  // after the joints: joined bodies do not collide
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
// The shared keys are read here (formulation_setup.hpp); the plugin reads its own keys,
// and every key is checked, when the analysis creates it.
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
    model_.formulation_options = read_formulation_options(node);
    model_.formulation_where = where(node);
}

// ---------------------------------------------------------------- bodies

void Loader::load_body(const Param& node, int index) {
    const bool planar = model_.dimension == Dimension::Planar;
    Body body;
    const std::string what =
        start_element(node, index, "body", "name, mass, inertia, position, ...", true, model_.bodies, body);

    if (planar)
        check_keys(node, what, {"name", "mass", "inertia", "position", "angle", "velocity", "angular_velocity", "visual"},
                   {{"orientation", "planar bodies take 'angle' (radians), not 'orientation'"},
                    {"collision", "collision shapes are spatial only; in a planar scene use the circle_line and "
                                  "circle_circle contact forces"}});
    else
        check_keys(node, what,
                   {"name", "mass", "inertia", "position", "orientation", "velocity", "angular_velocity", "visual",
                    "collision"},
                   {{"angle", "spatial bodies take 'orientation' ({euler_parameters: [..]}, {axis: [..], angle: ..} "
                              "or {matrix: [[..], [..], [..]]}), not 'angle'"}});

    if (body.name == "ground")
        find(node, "name")->fail("'ground' is reserved for the fixed ground; give the body another name");

    // zero mass and inertia are accepted: kinematics and statics do not need them; dynamics
    // refuses a singular mass matrix by name (core/src/simulation/simulation.cpp)
    const Param& mass = require(node, "mass", what, "a positive number, kg");
    body.mass = number(mass, "mass", what);
    if (!(body.mass >= 0)) mass.fail(what + ": 'mass' must be positive (or 0 for a massless body), got " + mass.text);

    const Param& inertia = require(node, "inertia", what,
                                   planar ? "a positive number, kg m^2 about the mass centre"
                                          : "[Ixx, Iyy, Izz] or a 3x3 matrix about the mass centre, body axes");
    body.inertia = body_inertia(inertia, what);

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
        if (const Param* o = find(node, "orientation")) body.euler_parameters = body_orientation(*o, what);
    }
    model_.bodies.push_back(std::move(body));
}

// `inertia:` about the mass centre: planar J; spatial [Ixx, Iyy, Izz] or a symmetric 3x3 matrix,
// each meeting the triangle inequality of principal moments.
Mat3 Loader::body_inertia(const Param& inertia, const std::string& what) const {
    Mat3 result = Mat3::Zero();
    if (model_.dimension == Dimension::Planar) {
        const double J = number(inertia, "inertia", what);
        if (!(J >= 0)) inertia.fail(what + ": 'inertia' must be positive (or 0), got " + inertia.text);
        result(2, 2) = J;
    } else {
        if (inertia.is_list() && !inertia.items.empty() && inertia.items[0].is_list()) {
            const Mat3 J = matrix3(inertia, "inertia", what);
            if (!J.isApprox(J.transpose(), 1e-9) && (J - J.transpose()).cwiseAbs().maxCoeff() > 1e-12)
                inertia.fail(what + ": 'inertia' matrix must be symmetric");
            const Mat3 Js = 0.5 * (J + J.transpose());
            const Eigen::SelfAdjointEigenSolver<Mat3> eig(Js);
            check_principal_moments(eig.eigenvalues(), inertia, what, "the principal moments (eigenvalues)");
            result = Js;
        } else {
            const Eigen::VectorXd d =
                vector(inertia, "inertia", what, 3, "[Ixx, Iyy, Izz] (or a 3x3 matrix)");
            for (int k = 0; k < 3; ++k)
                if (!(d[k] >= 0))
                    inertia.items[k].fail(what + ": 'inertia' moments must be positive (or 0), got " +
                                          inertia.items[k].text);
            check_principal_moments(d, inertia, what, "the principal moments [Ixx, Iyy, Izz]");
            result = d.asDiagonal();
        }
    }
    return result;
}

// `orientation:` of a spatial body: exactly one of {euler_parameters: [..]} (normalised),
// {axis: [..], angle: ..} or {matrix: [[..], [..], [..]]} (a rotation within 1e-6).
Vec4 Loader::body_orientation(const Param& o, const std::string& what) const {
    if (!o.is_map())
        o.fail(what + ": 'orientation' must be one of {euler_parameters: [e0, e1, e2, e3]}, "
                       "{axis: [x, y, z], angle: radians} or {matrix: [[..], [..], [..]]}");
    const bool has_ep = find(o, "euler_parameters"), has_axis = find(o, "axis"),
               has_angle = find(o, "angle"), has_matrix = find(o, "matrix");
    check_keys(o, what + " 'orientation'", {"euler_parameters", "axis", "angle", "matrix"});
    const int forms = int(has_ep) + int(has_axis || has_angle) + int(has_matrix);
    if (forms != 1)
        o.fail(what + ": 'orientation' takes exactly one of 'euler_parameters', 'axis' + 'angle' or 'matrix'");
    if (has_ep) {
        const Param& e = *find(o, "euler_parameters");
        Vec4 p = vector(e, "euler_parameters", what, 4, "[e0, e1, e2, e3]");
        if (!(p.norm() > 1e-12)) e.fail(what + ": 'euler_parameters' must not be all zero");
        return p / p.norm();
    } else if (has_matrix) {
        const Param& mp = *find(o, "matrix");
        const Mat3 A = matrix3(mp, "matrix", what);
        if ((A.transpose() * A - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6 || A.determinant() < 0)
            mp.fail(what + ": orientation 'matrix' must be a rotation matrix (orthonormal, determinant +1, "
                           "within 1e-6)");
        return euler_parameters_from_rotation(A);
    } else {
        if (!has_axis) o.fail(what + ": 'orientation' with 'angle' also needs 'axis: [x, y, z]'");
        if (!has_angle) o.fail(what + ": 'orientation' with 'axis' also needs 'angle' (radians)");
        const Param& ap = *find(o, "axis");
        const Vec3 axis = vector(ap, "axis", what, 3, "[x, y, z]");
        if (!(axis.norm() > 1e-12)) ap.fail(what + ": orientation 'axis' must not be the zero vector");
        const double angle = number(*find(o, "angle"), "angle", what);
        return euler_parameters_from_axis_angle(axis, angle);
    }
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

// ---------------------------------------------------------------- joints

void Loader::load_joint(const Param& node, int index) {
    const bool planar = model_.dimension == Dimension::Planar;
    JointInstance joint;
    const std::string what =
        start_element(node, index, "joint", "name, type, bodies, point, ...", true, model_.joints, joint);

    const Param& type = require(node, "type", what, "the joint type, e.g. revolute");
    if (!type.is_scalar() || type.text.empty()) type.fail(what + ": 'type' must be a single word, e.g. revolute");
    joint.type = type.text;

    const Param& bodies = require(node, "bodies", what, "[body_a, body_b], names of bodies or 'ground'");
    if (!bodies.is_list() || bodies.items.size() < 2 || bodies.items.size() > 4)
        bodies.fail(what + ": 'bodies' must list two body names [a, b] (a third for a carrier; up to four for a coordinate_coupling), got " +
                    (bodies.is_list() ? std::to_string(bodies.items.size()) + " items" : std::string("no list")));
    for (const auto& item : bodies.items)
        joint.bodies.push_back(element_body(item, what, static_cast<int>(joint.bodies.size()), joint.flexible));
    auto on_flexible = [&](size_t slot) {
        for (const FlexibleAttachment& a : joint.flexible)
            if (a.slot == static_cast<int>(slot)) return true;
        return false;
    };
    for (size_t a = 0; a < joint.bodies.size(); ++a)
        for (size_t b = a + 1; b < joint.bodies.size(); ++b)
            if (joint.bodies[a] == joint.bodies[b] && !on_flexible(a) && !on_flexible(b))
                bodies.fail(what + ": body " + quote(bodies.items[a].text) +
                            " appears twice in 'bodies'; a joint connects different bodies");

    Params params(what, &node);
    std::vector<std::string> core_keys{"name", "type", "bodies", "point", "axis", "limits"};
    if (!planar) {
        core_keys.push_back("x_axis");
        core_keys.push_back("axes");
    }
    for (const auto& k : core_keys) params.mark_read(k);

    WorldFrame frame = joint_frame(node, what, joint.type, joint.bodies, true);

    JointSpec spec;
    spec.name = joint.name;
    spec.type = joint.type;
    spec.dimension = model_.dimension;
    spec.bodies = element_body_infos(joint.bodies, joint.flexible);
    if (!find(node, "point"))  // at the first body's point: a flexible slot's material point counts
        for (size_t k = 0; k < joint.bodies.size(); ++k)
            if (!spec.bodies[k].ground) {
                frame.origin = spec.bodies[k].position;
                break;
            }
    for (const BodyInfo& b : spec.bodies)
        joint.markers.push_back(marker_in_frame(b.position, b.orientation, b.angle, frame.origin, frame.axes));
    spec.markers = joint.markers;
    spec.params = params;

    const std::string at = key_where(node, "type");
    const bool slider = joint.type == kBeamSliderType;  // the core's own joint type (beam_slider.hpp)
    if (const Param* axis = find(node, "axis"); slider && axis)
        axis->fail(what + ": a beam_slider has no axis (its collar's point slides along the flexible body's centre "
                          "line); remove 'axis'");
    joint.joint = create_checked(params, node, what, "joint", joint.type, [&]() -> std::shared_ptr<const Joint> {
        if (slider) return make_beam_slider(spec);
        return registry_.create_joint(spec, at);
    });
    if (!joint.joint) type.fail(what + ": the plugin for type " + quote(joint.type) + " created no joint");
    load_joint_limits(node, joint);
    if (slider) check_beam_slider(model_, joint);
    check_flexible_joint(joint);
    model_.joints.push_back(std::move(joint));
}
}  // namespace scene_detail

Scene read_scene_text(const std::string& yaml, const std::string& label, Registry& registry,
                      const std::vector<SceneSection>& sections) {
    scene_detail::Loader loader(label, registry, sections);
    return loader.load(yaml);
}

Scene read_scene(const std::filesystem::path& file, Registry& registry, const std::vector<SceneSection>& sections) {
    return read_scene_text(detail::read_scene_file(file), file.string(), registry, sections);
}

Model load_scene_text(const std::string& yaml, const std::string& label, Registry& registry) {
    return read_scene_text(yaml, label, registry).model;
}

Model load_scene(const std::filesystem::path& file, Registry& registry) {
    return read_scene(file, registry).model;
}

namespace {
std::mutex sections_mutex;
std::vector<SceneSection>& sections_declared() {
    static std::vector<SceneSection> declared;
    return declared;
}
}  // namespace

void declare_scene_sections(const std::vector<SceneSection>& sections) {
    const std::lock_guard<std::mutex> lock(sections_mutex);
    std::vector<SceneSection>& declared = sections_declared();
    for (const SceneSection& section : sections) {
        const auto same = std::find_if(declared.begin(), declared.end(),
                                       [&](const SceneSection& d) { return d.key == section.key; });
        if (same != declared.end()) *same = section;
        else declared.push_back(section);
    }
}

std::vector<SceneSection> declared_scene_sections() {
    const std::lock_guard<std::mutex> lock(sections_mutex);
    return sections_declared();
}

}  // namespace mbd
