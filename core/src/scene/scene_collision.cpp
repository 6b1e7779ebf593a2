// The scene loader's collision shapes: the `collision:` key of spatial bodies and of the
// top-level `ground:` (docs/scene-format.md "Collision shapes"). The core only gathers them:
// when any body or the ground has one, it adds one element of the force plugin
// `collision_contact` over every body that has shapes (plugins/forces/collision_contact/, which
// owns the detection with FCL and the contact laws), like the gravity element it adds for
// `gravity:`. A scene without shapes never opens that plugin, so it never loads FCL
// (docs/architecture.md "Collision detection").
#include "scene/scene_loader.hpp"

namespace mbd::scene_detail {

namespace {

Param scalar(const std::string& text, const Param& at) {
    Param p;
    p.text = text;
    p.file = at.file;
    p.line = at.line;
    return p;
}

// Whether the joint's slot is a point of a flexible body (its `bodies` entry holds the ground there).
bool on_flexible_body(const JointInstance& joint, size_t slot) {
    for (const FlexibleAttachment& a : joint.flexible)
        if (a.slot == static_cast<int>(slot)) return true;
    return false;
}

}  // namespace

// The element's keys, built here (the plugin reads them, the scene never writes them):
//   shapes: [{body: NAME, collision: <the body's `collision:` list as written>}, ...]
//   joined: [[k, l], ...]  positions in `shapes` of two bodies a joint connects
void Loader::add_collision_contact() {
    const Param* ground = find(root_, "ground");
    if (ground) {
        if (model_.dimension != Dimension::Spatial)
            ground->fail("scene: 'ground' (its collision shapes) is for spatial scenes; in a planar scene use the "
                         "circle_line contact force");
        if (!ground->is_map()) ground->fail("scene: 'ground' must be a map with the key 'collision'");
        check_keys(*ground, "'ground'", {"collision"});
    }
    const Param* bodies = find(root_, "bodies");  // absent in a scene of flexible bodies only
    ForceInstance force;
    force.name = "collision_contact";
    force.type = "collision_contact";
    Param shapes;
    shapes.kind = Param::Kind::List;
    auto add = [&](int body, const Param& collision) {
        if (force.bodies.empty()) {
            shapes.file = collision.file;
            shapes.line = collision.line;
            force.where = where(collision);
        }
        force.bodies.push_back(body);
        force.markers.emplace_back();
        Param entry;
        entry.kind = Param::Kind::Map;
        entry.file = collision.file;
        entry.line = collision.line;
        entry.fields["body"] = scalar(body == kGround ? "ground" : model_.bodies[body].name, collision);
        entry.fields["collision"] = collision;
        shapes.items.push_back(std::move(entry));
    };
    if (ground && find(*ground, "collision")) add(kGround, *find(*ground, "collision"));
    for (size_t k = 0; bodies && k < bodies->items.size(); ++k)
        if (const Param* c = find(bodies->items[k], "collision")) add(static_cast<int>(k), *c);
    if (force.bodies.empty()) return;

    Param joined;
    joined.kind = Param::Kind::List;
    for (const JointInstance& joint : model_.joints)
        for (size_t a = 0; a < joint.bodies.size(); ++a)
            for (size_t b = a + 1; b < joint.bodies.size(); ++b) {
                if (on_flexible_body(joint, a) || on_flexible_body(joint, b)) continue;  // its slot holds no ground
                const auto ia = std::find(force.bodies.begin(), force.bodies.end(), joint.bodies[a]);
                const auto ib = std::find(force.bodies.begin(), force.bodies.end(), joint.bodies[b]);
                if (ia == force.bodies.end() || ib == force.bodies.end()) continue;
                Param pair;
                pair.kind = Param::Kind::List;
                pair.items.push_back(scalar(std::to_string(ia - force.bodies.begin()), shapes));
                pair.items.push_back(scalar(std::to_string(ib - force.bodies.begin()), shapes));
                joined.items.push_back(std::move(pair));
            }

    Param node;
    node.kind = Param::Kind::Map;
    node.file = shapes.file;
    node.line = shapes.line;
    node.fields["shapes"] = std::move(shapes);
    node.fields["joined"] = std::move(joined);

    const std::string what = "the collision shapes";
    Params params(what, &node);
    const ForceSpec spec = force_spec(force, params);
    force.force = create_checked(params, node, what, "force", force.type,
                                 [&] { return registry_.create_force(spec, force.where); });
    if (!force.force) throw InputError(force.where, "the collision_contact plugin created no force");
    model_.forces.push_back(std::move(force));
}

}  // namespace mbd::scene_detail
