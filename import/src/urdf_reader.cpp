// URDF -> SourceTree (urdf_reader.hpp; docs/import.md, "URDF").
#include <mbd/import/urdf_reader.hpp>

#include <mbd/import/mesh_file.hpp>

#include <mbd/sdk/params.hpp>  // InputError

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <map>
#include <set>
#include <string>

namespace mbd::import {

namespace {

// urdfdom reports through console_bridge; its messages become the error's text.
class CapturedLog : public console_bridge::OutputHandler {
public:
    CapturedLog() { console_bridge::useOutputHandler(this); }
    ~CapturedLog() override { console_bridge::restorePreviousOutputHandler(); }
    void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
        if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) text_ += (text_.empty() ? "" : "; ") + text;
    }
    const std::string& text() const { return text_; }

private:
    std::string text_;
};

// Where each <link> and <joint> of the file is, and the link tree's parent joints.
struct Layout {
    std::map<std::string, std::string> link_where, joint_where;
};

// The file parsed by TinyXML (urdfdom's parser) for its lines, and the tree checked: every link
// the child of at most one joint, and no cycle of joints.
Layout check_layout(const std::string& file) {
    TiXmlDocument doc(file);
    if (!doc.LoadFile())
        throw InputError(file + ":" + std::to_string(doc.ErrorRow()),
                         std::string("malformed XML: ") + doc.ErrorDesc() + " (column " +
                             std::to_string(doc.ErrorCol()) + ")");
    Layout layout;
    const TiXmlElement* robot = doc.RootElement();
    if (!robot) throw InputError(file, "the URDF has no <robot> element");
    std::map<std::string, std::pair<std::string, std::string>> parent_of;  // child link -> (joint, parent link)
    for (const TiXmlElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
        const char* name = e->Attribute("name");
        const std::string at = file + ":" + std::to_string(e->Row());
        if (!name) continue;  // urdfdom names what is missing
        if (e->ValueStr() == "link") layout.link_where[name] = at;
        if (e->ValueStr() != "joint") continue;
        layout.joint_where[name] = at;
        const TiXmlElement* parent = e->FirstChildElement("parent");
        const TiXmlElement* child = e->FirstChildElement("child");
        if (!parent || !child || !parent->Attribute("link") || !child->Attribute("link")) continue;
        const std::string c = child->Attribute("link");
        auto [it, fresh] = parent_of.emplace(c, std::make_pair(std::string(name), std::string(parent->Attribute("link"))));
        if (!fresh)
            throw InputError(at, "URDF joint '" + std::string(name) + "': link '" + c + "' is already the child of joint '" +
                                     it->second.first + "'; a URDF is a tree, each link has one parent joint "
                                     "(closed loops cannot be written in URDF)");
    }
    for (const auto& [start, edge] : parent_of) {  // follow the parents: a cycle comes back
        std::set<std::string> seen{start};
        std::string link = start, path = "'" + edge.first + "'";
        for (auto it = parent_of.find(link); it != parent_of.end(); it = parent_of.find(link)) {
            link = it->second.second;
            if (link == start)
                throw InputError(layout.joint_where[edge.first],
                                 "URDF joints " + path + " form a cycle through link '" + start +
                                     "'; a URDF is a tree (closed loops cannot be written in URDF)");
            if (!seen.insert(link).second) break;  // a cycle that does not pass `start`: found from its own links
            if (parent_of.count(link)) path += ", '" + parent_of[link].first + "'";
        }
    }
    return layout;
}

Vec3 vec(const urdf::Vector3& v) { return Vec3(v.x, v.y, v.z); }
Mat3 rot(const urdf::Rotation& r) { return rotation_from_euler_parameters(Vec4(r.w, r.x, r.y, r.z).normalized()); }

struct Walker {
    const Layout& layout;
    SourceTree& tree;
    std::vector<std::string>& limited;
    std::vector<std::string>& friction;
    std::vector<std::string>& geometry;
    std::vector<std::string>& missing_meshes;
    std::vector<std::string>& undrawable_meshes;

    void add(const urdf::Link& link, int parent, const Vec3& origin, const Mat3& rotation) {
        SourceBody body;
        body.name = link.name;
        body.where = layout.link_where.count(link.name) ? layout.link_where.at(link.name) : tree.file;
        body.parent = parent;
        body.origin = origin;
        body.rotation = rotation;
        body.com = origin;
        if (link.inertial) {
            const urdf::Inertial& in = *link.inertial;
            body.mass = in.mass;
            Mat3 inertia;
            inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
            const Mat3 r = rot(in.origin.rotation);
            body.inertia = r * inertia * r.transpose();
            body.com = origin + rotation * vec(in.origin.position);
        }
        if (!link.collision_array.empty()) geometry.push_back(link.name);
        for (const urdf::VisualSharedPtr& v : link.visual_array)
            if (v && v->geometry) add_visual(body, *v, origin, rotation);
        if (link.parent_joint) body.joints = joints(*link.parent_joint, origin, rotation);
        tree.bodies.push_back(body);
        const int index = static_cast<int>(tree.bodies.size()) - 1;
        for (const urdf::JointSharedPtr& j : link.child_joints) {
            const urdf::Pose& pose = j->parent_to_joint_origin_transform;
            const urdf::LinkSharedPtr child = link.child_links.empty() ? nullptr : find_child(link, j->child_link_name);
            if (child) add(*child, index, origin + rotation * vec(pose.position), rotation * rot(pose.rotation));
        }
    }

    // A <visual> as a shape posed in world at t = 0 (the link frame at origin, rotation). A mesh is
    // looked for by its path (package:// and file:// taken off, relative to the URDF's folder); one
    // not found or that mbd cannot draw (only STL, OBJ, DAE and glTF) is listed, never an error: it has no dynamics.
    void add_visual(SourceBody& body, const urdf::Visual& v, const Vec3& origin, const Mat3& rotation) {
        VisualShape shape;
        shape.where = body.where + ": <visual> of link '" + body.name + "'";
        shape.position = origin + rotation * vec(v.origin.position);
        shape.rotation = rotation * rot(v.origin.rotation);
        if (v.material && v.material->color.a > 0)
            shape.color = Vec3(v.material->color.r, v.material->color.g, v.material->color.b);
        switch (v.geometry->type) {
            case urdf::Geometry::SPHERE:
                shape.kind = ShapeKind::Sphere;
                shape.radius = static_cast<const urdf::Sphere&>(*v.geometry).radius;
                break;
            case urdf::Geometry::BOX:
                shape.kind = ShapeKind::Box;
                shape.size = vec(static_cast<const urdf::Box&>(*v.geometry).dim);
                break;
            case urdf::Geometry::CYLINDER: {
                const auto& c = static_cast<const urdf::Cylinder&>(*v.geometry);
                shape.kind = ShapeKind::Cylinder;
                shape.radius = c.radius;
                shape.length = c.length;
                break;
            }
            case urdf::Geometry::MESH: {
                const auto& mesh = static_cast<const urdf::Mesh&>(*v.geometry);
                shape.kind = ShapeKind::Mesh;
                shape.scale = vec(mesh.scale);
                if (!mesh_path(mesh.filename, shape.mesh_file, body.name)) return;
                break;
            }
            default: return;
        }
        body.visuals.push_back(shape);
    }

    bool mesh_path(const std::string& filename, std::string& path, const std::string& link) {
        const MeshLookup found = find_mesh(filename, tree.file, path);
        if (found == MeshLookup::Missing) missing_meshes.push_back(filename + " (link '" + link + "')");
        if (found == MeshLookup::Undrawable) undrawable_meshes.push_back(filename + " (link '" + link + "')");
        return found == MeshLookup::Found;
    }

    static urdf::LinkSharedPtr find_child(const urdf::Link& link, const std::string& name) {
        for (const urdf::LinkSharedPtr& c : link.child_links)
            if (c->name == name) return c;
        return nullptr;
    }

    // The joint to the parent, in the child link's frame (origin, rotation: world).
    std::vector<SourceJoint> joints(const urdf::Joint& j, const Vec3& origin, const Mat3& rotation) {
        SourceJoint out;
        out.name = j.name;
        out.where = layout.joint_where.count(j.name) ? layout.joint_where.at(j.name) : tree.file;
        out.point = origin;
        const Vec3 axis = vec(j.axis);
        out.axis = axis.norm() > 0 ? Vec3(rotation * axis.normalized()) : Vec3(rotation * Vec3::UnitX());
        switch (j.type) {
            case urdf::Joint::REVOLUTE:
            case urdf::Joint::CONTINUOUS: out.kind = SourceJointKind::Hinge; break;
            case urdf::Joint::PRISMATIC: out.kind = SourceJointKind::Slide; break;
            case urdf::Joint::FLOATING: out.kind = SourceJointKind::Free; break;
            case urdf::Joint::PLANAR: out.kind = SourceJointKind::Planar; break;
            case urdf::Joint::FIXED: return {};
            default: throw InputError(out.where, "URDF joint '" + j.name + "': unknown joint type");
        }
        if (j.dynamics) {
            out.damping = j.dynamics->damping;
            if (j.dynamics->friction != 0.0) friction.push_back(j.name);
        }
        if (j.limits && j.type != urdf::Joint::CONTINUOUS) {
            if (j.limits->lower < j.limits->upper && (out.kind == SourceJointKind::Hinge || out.kind == SourceJointKind::Slide)) {
                out.limited = true;  // a hard limit; Gazebo gives a URDF limit SDF's default stiffness 1e8
                out.lower = j.limits->lower;
                out.upper = j.limits->upper;
            } else {
                limited.push_back(j.name + " (lower " + std::to_string(j.limits->lower) + " not below upper " +
                                  std::to_string(j.limits->upper) + ")");
            }
        }
        if (j.mimic)  // urdfdom does not check that the mimicked joint exists; the scene builder does
            tree.couplings.push_back({j.name, out.where, "URDF joint '" + j.name + "' <mimic>", j.name, j.mimic->joint_name,
                                      j.mimic->multiplier, j.mimic->offset});
        return {out};
    }
};

}  // namespace

SourceTree read_urdf(const std::filesystem::path& path) {
    const std::string file = path.string();
    const Layout layout = check_layout(file);
    urdf::ModelInterfaceSharedPtr model;
    std::string messages;
    {
        CapturedLog log;
        model = urdf::parseURDFFile(file);
        messages = log.text();
    }
    if (!model) {
        // urdfdom names a joint it refuses as "Joint [NAME]": point at its line
        std::string where = file;
        const size_t at = messages.find("Joint [");
        const size_t end = at == std::string::npos ? at : messages.find(']', at);
        if (end != std::string::npos) {
            const auto it = layout.joint_where.find(messages.substr(at + 7, end - at - 7));
            if (it != layout.joint_where.end()) where = it->second;
        }
        throw InputError(where, "urdfdom refused the URDF: " + (messages.empty() ? "no reason given" : messages));
    }
    SourceTree tree;
    tree.file = file;
    tree.format = "URDF";
    tree.name = model->getName();
    std::vector<std::string> limited, friction, geometry, missing_meshes, undrawable_meshes;
    Walker walker{layout, tree, limited, friction, geometry, missing_meshes, undrawable_meshes};
    walker.add(*model->getRoot(), -1, Vec3::Zero(), Mat3::Identity());
    auto add = [&](const std::string& kind, const std::vector<std::string>& names, const std::string& note) {
        if (!names.empty()) tree.unmapped.push_back({kind, names, note});
    };
    add("links' collision geometry", geometry, "contacts are not imported");
    add("visual meshes not found", missing_meshes, "not drawn; the dynamics do not depend on them");
    add("visual meshes mbd cannot draw", undrawable_meshes, "only STL, OBJ, DAE and glTF meshes are drawn");
    add("joint limits", limited, "an empty range is not imported as a stop");
    add("joint friction", friction, "");
    return tree;
}

}  // namespace mbd::import
