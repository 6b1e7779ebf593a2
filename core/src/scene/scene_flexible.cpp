// The scene's flexible bodies (`flexible_bodies:`, docs/scene-format.md): each a body plugin
// (sdk body.hpp) made from its keys, its coordinates after the rigid bodies'; and the joints and
// forces attached at their points, {body: NAME, node: K} or {body: NAME, at: xi} in a joint's `bodies`.
#include "scene/scene_loader.hpp"

#include <mbd/sdk/text.hpp>

#include <cmath>

namespace mbd::scene_detail {

void Loader::load_flexible_body(const Param& node, int index) {
    FlexibleBodyInstance body;
    const std::string what =
        start_element(node, index, "flexible body", "name, type, and the keys of its type", true,
                      model_.flexible_bodies, body);
    const Param* name = find(node, "name");
    if (body.name == "ground" || name_indexes_[&model_.bodies].find(model_.bodies, body.name) >= 0)
        name->fail(what + ": the name " + quote(body.name) +
                   (body.name == "ground" ? " is reserved for the fixed ground"
                                          : " is already a rigid body's (bodies and flexible bodies share names)") +
                   "; give the flexible body another name");
    const Param& type = require(node, "type", what, "the body type, e.g. ancf_cable");
    if (!type.is_scalar() || type.text.empty()) type.fail(what + ": 'type' must be a single word, e.g. ancf_cable");
    body.type = type.text;

    Params params(what, &node);
    params.mark_read("name");
    params.mark_read("type");
    BodySpec spec{body.name, body.type, model_.dimension, params};
    const std::string at = key_where(node, "type");
    body.body = create_checked(spec.params, node, what, "body", body.type,
                               [&] { return registry_.create_body(spec, at); });
    if (!body.body) type.fail(what + ": the plugin for type " + quote(body.type) + " created no body");
    model_.add_flexible_body(std::move(body));
}

std::vector<std::string> Loader::flexible_body_names() const {
    std::vector<std::string> names;
    for (const FlexibleBodyInstance& f : model_.flexible_bodies) names.push_back(f.name);
    return names;
}

int Loader::element_body(const Param& item, const std::string& what, int slot,
                         std::vector<FlexibleAttachment>& flexible) const {
    const bool on_flexible = item.is_map() || (item.is_scalar() && model_.flexible_body_index(item.text) >= 0);
    if (!on_flexible) return body_index(item, what);
    if (!item.is_map())
        item.fail(what + ": " + quote(item.text) + " is a flexible body; attach it at one of its points: {body: " +
                  item.text + ", node: K} (its node K, from 0) or {body: " + item.text +
                  ", at: xi} (its material parameter, the ancf_cable's arc length)");
    check_keys(item, what + " (a point of a flexible body)", {"body", "node", "at"});
    const Param& name = require(item, "body", what, "the flexible body's name");
    FlexibleAttachment attachment;
    attachment.slot = slot;
    attachment.body = model_.flexible_body_index(name.text);
    if (attachment.body < 0)
        name.fail(what + ": undefined flexible body " + quote(name.text) + "; defined flexible bodies are " +
                  (model_.flexible_bodies.empty() ? std::string("none (declare it under 'flexible_bodies:')")
                                                  : join_quoted(flexible_body_names())));
    const FlexibleBodyInstance& body = model_.flexible_bodies[attachment.body];
    const FlexibleBody& plugin = *body.body;
    const Param* node = find(item, "node");
    const Param* at = find(item, "at");
    if ((node != nullptr) == (at != nullptr))
        item.fail(what + ": give the point of flexible body " + quote(body.name) + " by 'node: K' or by 'at: xi', one of them");
    if (node) {
        const long long k = node->as_integer("node", 0, 1LL << 30, what);
        if (k >= plugin.node_count())
            node->fail(what + ": flexible body " + quote(body.name) + " (" + body.where + ") has nodes 0 to " +
                       std::to_string(plugin.node_count() - 1) + ", not " + node->text);
        attachment.xi = plugin.node_parameters(static_cast<int>(k));
    } else {
        const int n = plugin.material_parameters();
        attachment.xi = n == 1 && at->is_scalar() ? std::vector<double>{number(*at, "at", what)}
                                                  : [&] {
                                                        const Eigen::VectorXd v = vector(*at, "at", what, n, "(material parameters)");
                                                        return std::vector<double>(v.data(), v.data() + n);
                                                    }();
        try {
            plugin.check_material_point(attachment.xi.data());
        } catch (const InputError& outside) {
            at->fail(what + ": flexible body " + quote(body.name) + " (" + body.where + "): " + outside.message());
        }
    }
    flexible.push_back(std::move(attachment));
    return kGround;
}

std::vector<BodyInfo> Loader::element_body_infos(const std::vector<int>& bodies,
                                                 const std::vector<FlexibleAttachment>& flexible) const {
    std::vector<BodyInfo> infos;
    for (int b : bodies) infos.push_back(body_info(b));
    for (const FlexibleAttachment& a : flexible) infos[a.slot] = flexible_body_info(a);
    return infos;
}

BodyInfo Loader::flexible_body_info(const FlexibleAttachment& at) const {
    const FlexibleBodyInstance& body = model_.flexible_bodies[at.body];
    const Eigen::VectorXd q = body.body->initial_coordinates();
    MaterialFrame frame;
    body.body->frame(q, Eigen::VectorXd::Zero(q.size()), at.xi.data(), frame);
    BodyInfo info;
    info.name = body.name;
    if (model_.dimension == Dimension::Planar) {
        info.position = Vec3(frame.planar.R.x(), frame.planar.R.y(), 0.0);
        info.angle = frame.planar.theta;
        info.orientation = rotation_z(info.angle);
    } else {
        info.position = frame.spatial.R;
        info.orientation = frame.spatial.A;
    }
    return info;
}

void Loader::check_flexible_joint(const JointInstance& joint) const {
    if (joint.flexible.empty() || joint.joint->velocity_rows() == 0) return;
    throw InputError(joint.where, "joint " + quote(joint.name) + " (type " + joint.type +
                                      ") has velocity-level rows and is attached to flexible body " +
                                      quote(model_.flexible_bodies[joint.flexible.front().body].name) +
                                      ", which the engine does not map yet; attach it to rigid bodies");
}

}  // namespace mbd::scene_detail
