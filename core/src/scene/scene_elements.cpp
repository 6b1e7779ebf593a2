// The scene loader's sections for forces, drivers, joint limits, actuators and the gravity
// force (see scene.cpp and docs/scene-format.md).
#include "scene/scene_loader.hpp"

#include <algorithm>
#include <optional>

namespace mbd::scene_detail {

int Loader::coordinate_joint(const Param& joint, const std::string& what, const std::string& purpose) const {
    if (!joint.is_scalar() || joint.text.empty()) joint.fail(what + ": 'joint' must be a joint name");
    int index = -1;
    for (int k = 0; k < static_cast<int>(model_.joints.size()); ++k)
        if (model_.joints[k].name == joint.text) index = k;
    if (index < 0) {
        std::vector<std::string> names;
        for (const auto& j : model_.joints) names.push_back(j.name);
        joint.fail(what + ": undefined joint " + quote(joint.text) + "; defined joints are " +
                   (names.empty() ? std::string("(none)") : join_quoted(names)));
    }
    const JointInstance& target = model_.joints[index];
    if (!target.joint->has_coordinate())
        joint.fail(what + ": joint " + quote(target.name) + " (" + target.type + ") has no single coordinate " +
                   purpose);
    return index;
}


// ---------------------------------------------------------------- forces

void Loader::add_gravity() {
    ForceInstance force;
    force.name = "gravity";
    force.type = "gravity";
    force.where = key_where(root_, "gravity");
    force.constant_load = true;
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

// `body: NAME` or `bodies: [a, b, ...]` of a force element: named bodies, each once, not the
// ground alone; a point of a flexible body, {body: NAME, node: K} or {body: NAME, at: xi}, is
// a slot on its material frame (added to `flexible`).
std::vector<int> Loader::force_bodies(const Param& node, const std::string& what,
                                      std::vector<FlexibleAttachment>& flexible) const {
    std::vector<int> indices;
    const Param* body = find(node, "body");
    const Param* bodies = find(node, "bodies");
    if (body && bodies) body->fail(what + ": give either 'body: NAME' or 'bodies: [a, b]', not both");
    if (!body && !bodies)
        throw InputError(where(node), what + " needs 'body: NAME' (one body) or 'bodies: [a, b]' (two bodies)");
    if (body) {
        indices.push_back(element_body(*body, what, 0, flexible));
    } else {
        if (!bodies->is_list() || bodies->items.empty())
            bodies->fail(what + ": 'bodies' must be a list of body names [a, b]");
        for (const auto& item : bodies->items)
            indices.push_back(element_body(item, what, static_cast<int>(indices.size()), flexible));
    }
    const Param& body_list = body ? *body : *bodies;
    if (indices.size() == 1 && indices[0] == kGround && flexible.empty())
        body_list.fail(what + ": a force on the ground alone has no effect; apply it to a moving body");
    auto rigid = [&](size_t slot) {
        return std::none_of(flexible.begin(), flexible.end(),
                            [&](const FlexibleAttachment& a) { return a.slot == static_cast<int>(slot); });
    };
    for (size_t a = 0; a < indices.size(); ++a)
        for (size_t b = a + 1; b < indices.size(); ++b)
            if (indices[a] == indices[b] && rigid(a) && rigid(b))
                body_list.fail(what + ": a body appears twice in 'bodies'; a force connects different bodies");
    return indices;
}

// The markers of a force element's bodies: one body's `point` (its own frame, default the mass
// centre); one `points` entry per body (each body's frame); a world `point` / `axis` giving a
// joint-like frame at t = 0; else each body's mass centre.
std::vector<Marker> Loader::force_markers(const Param& node, const std::string& what, const ForceInstance& force,
                                          Params& params) const {
    const bool planar = model_.dimension == Dimension::Planar;
    const bool single = force.bodies.size() == 1;
    std::vector<Marker> markers;
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
        markers.push_back(m);
    } else if (points) {
        // one point per body, each in that body's own frame, body-aligned axes
        if (!points->is_list() || points->items.size() != force.bodies.size())
            points->fail(what + ": 'points' must list one point per body (" + std::to_string(force.bodies.size()) +
                         "), each in that body's own frame");
        for (const auto& p : points->items) {
            Marker m;
            m.u_bar = space_vector(p, "points", what);
            markers.push_back(m);
        }
        if (axis || x_axis)
            (axis ? axis : x_axis)
                ->fail(what + ": 'axis' / 'x_axis' go with a world 'point' (a joint-like frame), not with 'points'");
    } else if (point || axis) {
        // a joint-like frame in world at t = 0: markers coincide at the point
        params.mark_read("axis");
        if (!planar) params.mark_read("x_axis");
        WorldFrame frame = joint_frame(node, what, force.type, force.bodies, false);
        const std::vector<BodyInfo> infos = element_body_infos(force.bodies, force.flexible);
        if (!point)  // at the first body's point, as joints: a flexible slot's material point counts
            for (const BodyInfo& b : infos)
                if (!b.ground) {
                    frame.origin = b.position;
                    break;
                }
        for (const BodyInfo& b : infos)
            markers.push_back(marker_in_frame(b.position, b.orientation, b.angle, frame.origin, frame.axes));
    } else {
        // default: each body's mass centre, body-aligned axes
        for (size_t k = 0; k < force.bodies.size(); ++k) markers.emplace_back();
    }
    return markers;
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
    require_unique_name(model_.forces, force.name, node, "force");

    force.bodies = force_bodies(node, what, force.flexible);

    Params params(what, &node);
    for (const auto& k : {"name", "type", "body", "bodies", "point", "points"}) params.mark_read(k);
    force.markers = force_markers(node, what, force, params);

    const ForceSpec spec = force_spec(force, params);

    const std::string at = key_where(node, "type");
    force.force = create_checked(params, node, what, "force", force.type, [&] { return registry_.create_force(spec, at); });
    if (!force.force) type.fail(what + ": the plugin for type " + quote(force.type) + " created no force");
    force.load_joint = reaction_load_joint(node, what, force);
    check_stop_coordinate(node, what, force);
    model_.forces.push_back(std::move(force));
}

// A joint_stop limits the coordinate a joint between its two bodies measures: its `coordinate`
// (angle or travel) must be one that such a joint has, or the stop never acts (a travel
// across a revolute joint). Joints that do not describe their relative motion are not judged;
// a stop between bodies that no joint connects is left alone.
void Loader::check_stop_coordinate(const Param& node, const std::string& what, const ForceInstance& force) const {
    if (force.type != "joint_stop" || force.bodies.size() != 2 || !force.flexible.empty()) return;
    const Param* key = find(node, "coordinate");
    const bool travel = key && key->text == "travel";
    std::vector<int> mine = force.bodies;
    std::sort(mine.begin(), mine.end());
    const JointInstance* other = nullptr;
    std::string other_has;
    for (const JointInstance& joint : model_.joints) {
        std::vector<int> theirs = joint.bodies;
        std::sort(theirs.begin(), theirs.end());
        const std::optional<RelativeMotion> motion = joint.joint->relative_motion();
        if (theirs != mine || !motion) continue;
        bool angle = false, translation = false;
        for (const RelativeMotion::Freedom& f : motion->freedoms) {
            angle = angle || f.kind != RelativeMotion::Kind::Prismatic;
            translation = translation || f.kind == RelativeMotion::Kind::Prismatic ||
                          f.kind == RelativeMotion::Kind::Helical;
        }
        if (travel ? translation : angle) return;  // this joint measures the stop's coordinate
        other = &joint;
        other_has = angle ? "an angle ('coordinate: angle')" : translation ? "a travel ('coordinate: travel')"
                                                                            : "no free motion";
    }
    if (!other) return;
    const std::string message = what + ": 'coordinate: " + (travel ? "travel" : "angle") + "', but joint " +
                                quote(other->name) + " (" + other->type + ") between its bodies has " + other_has +
                                ", so the stop would never act; give the coordinate that joint has";
    if (key) key->fail(message);
    node.fail(message);
}

// The joint whose reaction loads a force element (Force::load_joint(), the plugin's key
// `load_joint`): a joint of the scene that connects the element's two bodies.
int Loader::reaction_load_joint(const Param& node, const std::string& what, const ForceInstance& force) const {
    const std::string name = force.force->load_joint();
    if (name.empty()) return -1;
    const Param* key = find(node, "load_joint");
    auto fail = [&](const std::string& message) {
        if (key) key->fail(message);
        node.fail(message);
    };
    if (!force.flexible.empty())
        fail(what + ": 'load_joint' on a force at flexible body " +
             quote(model_.flexible_bodies[force.flexible.front().body].name) +
             " is not mapped (a joint's reaction at a flexible body is not computed); give a fixed load instead");
    int index = -1;
    for (int k = 0; k < static_cast<int>(model_.joints.size()); ++k)
        if (model_.joints[k].name == name) index = k;
    if (index < 0) {
        std::vector<std::string> names;
        for (const auto& j : model_.joints) names.push_back(j.name);
        fail(what + ": 'load_joint' names undefined joint " + quote(name) + " (joints are listed before forces: " +
             (names.empty() ? std::string("none") : join_quoted(names)) + ")");
    }
    std::vector<int> mine = force.bodies, theirs = model_.joints[index].bodies;
    std::sort(mine.begin(), mine.end());
    std::sort(theirs.begin(), theirs.end());
    if (mine != theirs)
        fail(what + ": 'load_joint' " + quote(name) + " does not connect the force's bodies; the friction of a "
             "joint acts between the two bodies the joint connects, so list the same bodies");
    return index;
}

// ---------------------------------------------------------------- drivers

void Loader::load_driver(const Param& node, int index) {
    Driver driver;
    const std::string what = open_element(node, index, "driver", {"name", "joint", "motion"}, model_.drivers, driver);

    const Param& joint = require(node, "joint", what, "the name of the joint whose coordinate it prescribes");
    driver.joint = coordinate_joint(joint, what, "to drive; drive a revolute, prismatic or other 1-DOF joint");
    const JointInstance& target = model_.joints[driver.joint];
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
    Actuator actuator;
    const std::string what =
        open_element(node, index, "actuator", {"name", "joint", "bounds", "weight"}, model_.actuators, actuator);
    const Param& joint = require(node, "joint", what, "the name of the joint along whose coordinate it acts");
    actuator.joint = coordinate_joint(joint, what, "to act along; use a revolute, prismatic or other 1-DOF joint");
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

}  // namespace mbd::scene_detail
