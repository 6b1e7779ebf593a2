// SDF -> SourceTree (sdf_reader.hpp; docs/import.md, "SDF"). Every pose and axis is asked of
// libsdformat in the model frame (`__model__`), so its frame semantics apply exactly.
#include <mbd/import/sdf_reader.hpp>

#include <mbd/import/mesh_file.hpp>
#include <mbd/sdk/params.hpp>  // InputError

#include <sdf/Console.hh>
#include <sdf/Element.hh>
#include <sdf/Joint.hh>
#include <sdf/JointAxis.hh>
#include <sdf/Link.hh>
#include <sdf/Model.hh>
#include <sdf/Root.hh>
#include <sdf/SemanticPose.hh>
#include <sdf/Box.hh>
#include <sdf/Capsule.hh>
#include <sdf/Cylinder.hh>
#include <sdf/Geometry.hh>
#include <sdf/Material.hh>
#include <sdf/Mesh.hh>
#include <sdf/Sphere.hh>
#include <sdf/Visual.hh>
#include <sdf/World.hh>

#include <tinyxml.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

namespace mbd::import {

namespace {

const std::string kModelFrame = "__model__";

Vec3 vec(const ignition::math::Vector3d& v) { return Vec3(v.X(), v.Y(), v.Z()); }
Mat3 rot(const ignition::math::Quaterniond& q) {
    return rotation_from_euler_parameters(Vec4(q.W(), q.X(), q.Y(), q.Z()).normalized());
}

// "file:line" of an element, the file alone when libsdformat has no line for it.
std::string where(const sdf::ElementPtr& element, const std::string& file) {
    if (!element) return file;
    const std::string path = element->FilePath().empty() ? file : element->FilePath();
    const std::optional<int> line = element->LineNumber();
    return line ? path + ":" + std::to_string(*line) : path;
}

// libsdformat's errors as one InputError at the first error's file:line.
void throw_errors(const sdf::Errors& errors, const std::string& file, const std::string& what) {
    if (errors.empty()) return;
    // the first error is the cause; libsdformat's graph checks add consequences of it
    std::string text = errors.front().Message();
    if (errors.size() > 1) text += " (and " + std::to_string(errors.size() - 1) + " errors that follow from it)";
    std::string at = errors.front().FilePath().value_or(file);
    if (errors.front().LineNumber()) at += ":" + std::to_string(*errors.front().LineNumber());
    throw InputError(at, "libsdformat " + what + ": " + text);
}

// A pose as (origin, rotation) in world axes, given the model's placement.
struct Placement {
    Vec3 origin = Vec3::Zero();
    Mat3 rotation = Mat3::Identity();
    Vec3 point(const ignition::math::Vector3d& p) const { return origin + rotation * vec(p); }
};

class SdfReader {
public:
    SdfReader(const sdf::Model& model, const Placement& placement, SourceTree& tree)
        : model_(model), placement_(placement), tree_(tree) {}

    void read() {
        map_joints();
        for (uint64_t k = 0; k < model_.LinkCount(); ++k) {  // roots first: links no joint moves
            const sdf::Link& link = *model_.LinkByIndex(k);
            if (!parent_joint_.count(link.Name())) add(link, -1, nullptr);
        }
        for (const std::string& child : children_["world"])  // links jointed to the world
            if (const sdf::Link* c = model_.LinkByName(child)) add(*c, -1, parent_joint_.at(child));
        for (uint64_t k = 0; k < model_.LinkCount(); ++k) {
            const std::string& name = model_.LinkByIndex(k)->Name();
            if (!index_.count(name))
                throw InputError(where(model_.LinkByIndex(k)->Element(), tree_.file),
                                 "SDF link '" + name + "' is reached by no chain of joints from the world or a free "
                                 "link: its joints form a cycle (each link needs one parent joint, ending at a link "
                                 "that has none or at `world`)");
        }
        for (const LoopJoint& loop : loop_joints_) add_loop(loop);
        auto add_unmapped = [&](const std::string& kind, const std::vector<std::string>& names, const std::string& note) {
            if (!names.empty()) tree_.unmapped.push_back({kind, names, note});
        };
        add_unmapped("links' collision geometry", geometry_, "contacts are not imported");
        add_unmapped("visual meshes not found", missing_meshes_, "not drawn; the dynamics do not depend on them");
        add_unmapped("visual meshes mbd cannot draw", undrawable_meshes_, "only STL, OBJ, DAE and glTF meshes are drawn");
        add_unmapped("sensors", sensors_, "");
        add_unmapped("joint limits", limited_, "limits of ball, universal and screw joints, and empty ranges, are not imported");
        add_unmapped("joint friction", friction_, "");
        add_unmapped("gearbox joints", gearbox_, "no gear coupling of spatial joints yet");
        add_unmapped("loop-closing joints", loops_, "revolute2 loop-closing joints are not imported");
        add_unmapped("loop-closing joints' limits, springs and damping", loop_passive_, "");
    }

private:
    // The joint that moves each link (its child); a second joint into the same link closes a loop.
    void map_joints() {
        for (uint64_t k = 0; k < model_.JointCount(); ++k) {
            const sdf::Joint& joint = *model_.JointByIndex(k);
            const std::string at = where(joint.Element(), tree_.file);
            std::string child, parent;
            throw_errors(joint.ResolveChildLink(child), tree_.file, "could not resolve the child of joint '" + joint.Name() + "'");
            throw_errors(joint.ResolveParentLink(parent), tree_.file, "could not resolve the parent of joint '" + joint.Name() + "'");
            if (joint.SensorCount() > 0) sensors_.push_back(joint.Name());
            if (joint.Type() == sdf::JointType::GEARBOX) {
                gearbox_.push_back(joint.Name() + " (" + at + ")");
                continue;
            }
            if (parent_joint_.count(child)) {  // closes a loop: mapped once every link is placed
                loop_joints_.push_back({&joint, parent, child});
                continue;
            }
            parent_joint_[child] = &joint;
            children_[parent].push_back(child);
        }
    }

    // A <visual> as a shape posed in world at t = 0 (as a URDF one, urdf_reader.cpp add_visual).
    void add_visual(SourceBody& body, const sdf::Visual& v) {
        const sdf::Geometry& g = *v.Geom();
        VisualShape shape;
        shape.where = where(v.Element(), tree_.file) + ": <visual> '" + v.Name() + "' of link '" + body.name + "'";
        ignition::math::Pose3d pose;
        throw_errors(v.SemanticPose().Resolve(pose, kModelFrame), tree_.file, "could not resolve the pose of visual '" + v.Name() + "'");
        shape.position = placement_.point(pose.Pos());
        shape.rotation = placement_.rotation * rot(pose.Rot());
        if (v.Material()) {  // a material given by a script only keeps libsdformat's black diffuse: grey then
            const ignition::math::Color c = v.Material()->Diffuse();
            if (c.R() + c.G() + c.B() > 0) shape.color = Vec3(c.R(), c.G(), c.B());
        }
        switch (g.Type()) {
            case sdf::GeometryType::BOX: shape.kind = ShapeKind::Box; shape.size = vec(g.BoxShape()->Size()); break;
            case sdf::GeometryType::SPHERE: shape.kind = ShapeKind::Sphere; shape.radius = g.SphereShape()->Radius(); break;
            case sdf::GeometryType::CYLINDER:
                shape.kind = ShapeKind::Cylinder;
                shape.radius = g.CylinderShape()->Radius();
                shape.length = g.CylinderShape()->Length();
                break;
            case sdf::GeometryType::CAPSULE:
                shape.kind = ShapeKind::Capsule;
                shape.radius = g.CapsuleShape()->Radius();
                shape.length = g.CapsuleShape()->Length();
                break;
            case sdf::GeometryType::MESH: {
                shape.kind = ShapeKind::Mesh;
                shape.scale = vec(g.MeshShape()->Scale());
                const std::string uri = g.MeshShape()->Uri();
                const MeshLookup found = find_mesh(uri, tree_.file, shape.mesh_file);
                if (found == MeshLookup::Missing) missing_meshes_.push_back(uri + " (link '" + body.name + "')");
                if (found == MeshLookup::Undrawable) undrawable_meshes_.push_back(uri + " (link '" + body.name + "')");
                if (found != MeshLookup::Found) return;
                break;
            }
            default: return;
        }
        body.visuals.push_back(shape);
    }

    // Link `link` (moved by `joint`, nullptr: free or welded to the world) and its subtree.
    void add(const sdf::Link& link, int parent, const sdf::Joint* joint) {
        SourceBody body;
        body.name = link.Name();
        body.where = where(link.Element(), tree_.file);
        body.parent = parent;
        ignition::math::Pose3d pose;
        throw_errors(link.SemanticPose().Resolve(pose, kModelFrame), tree_.file, "could not resolve the pose of link '" + link.Name() + "'");
        body.origin = placement_.point(pose.Pos());
        body.rotation = placement_.rotation * rot(pose.Rot());
        const ignition::math::Inertiald& inertial = link.Inertial();
        body.mass = inertial.MassMatrix().Mass();
        const ignition::math::Matrix3d moi = inertial.Moi();  // about the mass centre, link axes
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) body.inertia(r, c) = moi(r, c);
        body.com = body.origin + body.rotation * vec(inertial.Pose().Pos());
        if (link.CollisionCount() > 0) geometry_.push_back(link.Name());
        for (uint64_t v = 0; v < link.VisualCount(); ++v) add_visual(body, *link.VisualByIndex(v));
        if (link.SensorCount() > 0) sensors_.push_back(link.Name());
        if (joint) {
            body.joints = joints(*joint);
        } else if (!model_.Static()) {  // a link no joint holds moves freely (SDF, Gazebo)
            SourceJoint free;
            free.name = link.Name() + "_free";
            free.where = body.where;
            free.kind = SourceJointKind::Free;
            free.point = body.origin;
            body.joints.push_back(free);
        }
        tree_.bodies.push_back(body);
        const int index = static_cast<int>(tree_.bodies.size()) - 1;
        index_[link.Name()] = index;
        for (const std::string& child : children_[link.Name()])
            if (const sdf::Link* c = model_.LinkByName(child)) add(*c, index, parent_joint_.at(child));
    }

    Vec3 axis(const sdf::Joint& joint, unsigned k) const {
        const sdf::JointAxis* a = joint.Axis(k);
        if (!a) throw InputError(where(joint.Element(), tree_.file), "SDF joint '" + joint.Name() + "' has no <axis" +
                                                                         (k ? "2" : "") + ">, which its type needs");
        ignition::math::Vector3d xyz;
        throw_errors(a->ResolveXyz(xyz, kModelFrame), tree_.file, "could not resolve the axis of joint '" + joint.Name() + "'");
        return (placement_.rotation * vec(xyz)).normalized();
    }

    std::vector<SourceJoint> joints(const sdf::Joint& joint) {
        SourceJoint out;
        out.name = joint.Name();
        out.where = where(joint.Element(), tree_.file);
        ignition::math::Pose3d pose;
        throw_errors(joint.SemanticPose().Resolve(pose, kModelFrame), tree_.file, "could not resolve the pose of joint '" + joint.Name() + "'");
        out.point = placement_.point(pose.Pos());
        switch (joint.Type()) {
            case sdf::JointType::FIXED: return {};
            case sdf::JointType::BALL: out.kind = SourceJointKind::Ball; return {out};
            case sdf::JointType::REVOLUTE:
            case sdf::JointType::CONTINUOUS: out.kind = SourceJointKind::Hinge; break;
            case sdf::JointType::PRISMATIC: out.kind = SourceJointKind::Slide; break;
            case sdf::JointType::SCREW:
                out.kind = SourceJointKind::Screw;
                // SDF's thread_pitch is in rad/m with Gazebo's sign: a positive value advances
                // along -axis on a positive turn (SDF 1.10: screw_thread_pitch = -2 pi / thread_pitch)
                if (joint.ThreadPitch() == 0.0 || !std::isfinite(joint.ThreadPitch()))
                    throw InputError(out.where, "SDF screw joint '" + joint.Name() + "': thread_pitch " +
                                                    std::to_string(joint.ThreadPitch()) + " is not a pitch (give a finite non-zero value, rad/m)");
                out.pitch = -2.0 * M_PI / joint.ThreadPitch();
                break;
            case sdf::JointType::UNIVERSAL: out.kind = SourceJointKind::Universal; break;
            case sdf::JointType::REVOLUTE2: {  // two hinges in series: the first fixed in the parent
                out.kind = SourceJointKind::Hinge;
                out.axis = axis(joint, 0);
                read_passive(joint, 0, out);
                SourceJoint second = out;
                second.name = joint.Name() + "_axis2";
                second.axis = axis(joint, 1);
                read_passive(joint, 1, second);
                return {out, second};
            }
            default:
                throw InputError(out.where, "SDF joint '" + joint.Name() + "': its type is not one mbd maps (revolute, "
                                            "continuous, prismatic, ball, universal, revolute2, screw, fixed)");
        }
        out.axis = axis(joint, 0);
        if (out.kind == SourceJointKind::Universal) {
            out.axis2 = axis(joint, 1);
            if (std::abs(out.axis.dot(out.axis2)) > 1e-6)
                throw InputError(out.where, "SDF universal joint '" + joint.Name() + "': its two axes are not perpendicular "
                                            "(cosine " + std::to_string(out.axis.dot(out.axis2)) + "); mbd's universal "
                                            "joint is a Hooke joint with perpendicular axes (use revolute2 otherwise)");
        }
        read_passive(joint, 0, out);
        return {out};
    }

    // Spring, damping, friction and limits of axis k.
    void read_passive(const sdf::Joint& joint, unsigned k, SourceJoint& out) {
        const sdf::JointAxis* a = joint.Axis(k);
        if (!a) return;
        const bool one_coordinate = out.kind == SourceJointKind::Hinge || out.kind == SourceJointKind::Slide;
        if (one_coordinate) {
            out.damping = a->Damping();
            out.stiffness = a->SpringStiffness();
            out.spring_reference = a->SpringReference();
        } else if (a->Damping() != 0.0 || a->SpringStiffness() != 0.0) {
            friction_.push_back(out.name + " (spring / damping)");
        }
        if (a->Friction() != 0.0) friction_.push_back(out.name);
        const bool continuous = joint.Type() == sdf::JointType::CONTINUOUS;
        if (continuous || (a->Lower() <= -1e15 && a->Upper() >= 1e15)) return;  // SDF's "no limit" is +-1e16
        if (one_coordinate && a->Lower() < a->Upper() && a->Stiffness() > 0.0) {
            out.limited = true;
            out.lower = a->Lower();
            out.upper = a->Upper();
            out.stop_stiffness = a->Stiffness();
        } else {
            limited_.push_back(out.name);
        }
    }

    struct LoopJoint {
        const sdf::Joint* joint;
        std::string parent, child;
    };

    // A second joint into a link: a constraint between two placed links (a fixed one a weld).
    void add_loop(const LoopJoint& loop) {
        const std::vector<SourceJoint> mapped = joints(*loop.joint);
        if (mapped.size() > 1) {
            loops_.push_back(loop.joint->Name() + " (" + where(loop.joint->Element(), tree_.file) + ")");
            return;
        }
        SourceLoop out;
        out.weld = mapped.empty();
        if (out.weld) {
            out.joint.name = loop.joint->Name();
            out.joint.where = where(loop.joint->Element(), tree_.file);
            ignition::math::Pose3d pose;
            throw_errors(loop.joint->SemanticPose().Resolve(pose, kModelFrame), tree_.file, "could not resolve the pose of joint '" + loop.joint->Name() + "'");
            out.joint.point = placement_.point(pose.Pos());
        } else {
            out.joint = mapped.front();
        }
        if (out.joint.limited || out.joint.stiffness != 0.0 || out.joint.damping != 0.0) loop_passive_.push_back(out.joint.name);
        out.body_a = loop.parent == "world" ? -1 : index_.at(loop.parent);
        out.body_b = index_.at(loop.child);
        tree_.loops.push_back(out);
    }

    const sdf::Model& model_;
    Placement placement_;
    SourceTree& tree_;
    std::map<std::string, const sdf::Joint*> parent_joint_;      // child link -> its joint
    std::map<std::string, std::vector<std::string>> children_;  // parent link ("world") -> child links
    std::map<std::string, int> index_;                          // link -> SourceTree::bodies index
    std::vector<LoopJoint> loop_joints_;
    std::vector<std::string> geometry_, sensors_, limited_, friction_, gearbox_, loops_, loop_passive_, missing_meshes_, undrawable_meshes_;
};

}  // namespace

SourceTree read_sdf(const std::filesystem::path& path) {
    const std::string file = path.string();
    // libsdformat reports malformed XML only as "Unable to read file" (the line goes to its
    // console): TinyXML, the URDF reader's parser, names the line first
    TiXmlDocument xml(file);
    if (!xml.LoadFile())
        throw InputError(file + ":" + std::to_string(xml.ErrorRow()),
                         std::string("malformed XML: ") + xml.ErrorDesc() + " (column " + std::to_string(xml.ErrorCol()) + ")");
    sdf::Console::Instance()->SetQuiet(true);  // its warnings go to stderr otherwise; errors are returned
    sdf::Root root;
    throw_errors(root.Load(file), file, "refused the SDF file");
    SourceTree tree;
    tree.file = file;
    tree.format = "SDF";
    tree.gravity = Vec3(0, 0, -9.8);  // SDF's <world><gravity> default, for a file that is one model
    const sdf::Model* model = root.Model();
    Placement placement;
    if (!model) {
        const sdf::World* world = root.WorldCount() > 0 ? root.WorldByIndex(0) : nullptr;
        if (!world || world->ModelCount() != 1)
            throw InputError(file, "the SDF file holds " + std::string(world ? std::to_string(world->ModelCount()) + " models in its first world"
                                                                               : "no model and no world") +
                                       ": mbd imports one model (a <model>, or a <world> with one <model>)");
        tree.gravity = vec(world->Gravity());
        model = world->ModelByIndex(0);
        ignition::math::Pose3d pose;
        throw_errors(model->SemanticPose().Resolve(pose, "world"), file, "could not place the model in its world");
        placement = {vec(pose.Pos()), rot(pose.Rot())};
    } else {
        placement = {vec(model->RawPose().Pos()), rot(model->RawPose().Rot())};
    }
    tree.name = model->Name();
    if (model->ModelCount() > 0) {
        std::vector<std::string> nested;
        for (uint64_t k = 0; k < model->ModelCount(); ++k) nested.push_back(model->ModelByIndex(k)->Name());
        tree.unmapped.push_back({"nested models", nested, "their links and joints are not imported"});
    }
    SdfReader(*model, placement, tree).read();
    return tree;
}

}  // namespace mbd::import
