// ExportTree -> MJCF (model_writers.hpp). Each body's frame is its mass centre and body axes, so
// its <inertial> sits at the origin with the full inertia tensor; joints are placed in the
// child's frame as MuJoCo reads them (docs/import.md, "Export").
#include <mbd/import/model_writers.hpp>

#include "xml_text.hpp"

#include <map>

namespace mbd::import {

namespace {

const char* joint_type(ExportJointKind kind) {
    switch (kind) {
        case ExportJointKind::Hinge: return "hinge";
        case ExportJointKind::Slide: return "slide";
        case ExportJointKind::Ball: return "ball";
        case ExportJointKind::Free: break;
    }
    return "free";
}

class MjcfWriter {
public:
    explicit MjcfWriter(const ExportTree& tree) : tree_(tree) {
        for (size_t b = 0; b < tree.bodies.size(); ++b)
            (tree.bodies[b].parent < 0 ? roots_ : children_[tree.bodies[b].parent]).push_back(static_cast<int>(b));
    }

    std::string text() {
        TiXmlDocument document;
        TiXmlElement* mujoco = xml::child(&document, "mujoco");
        mujoco->SetAttribute("model", tree_.name);
        std::string note = " Written by mbd export from " + tree_.source + " (docs/import.md). ";
        if (tree_.planar) note += "A planar scene: its motion lies in the x-y plane. ";
        mujoco->LinkEndChild(new TiXmlComment(note.c_str()));
        TiXmlElement* compiler = xml::child(mujoco, "compiler");
        compiler->SetAttribute("angle", "radian");
        compiler->SetAttribute("inertiafromgeom", "false");
        TiXmlElement* option = xml::child(mujoco, "option");
        option->SetAttribute("gravity", xml::xyz(tree_.gravity));
        option->SetAttribute("integrator", "RK4");
        TiXmlElement* world = xml::child(mujoco, "worldbody");
        for (int b : roots_) write_body(world, b, Vec3::Zero(), Mat3::Identity());
        if (!qvel_.empty()) {
            TiXmlElement* key = xml::child(xml::child(mujoco, "keyframe"), "key");
            key->SetAttribute("name", "start");
            key->SetAttribute("qvel", xml::numbers(qvel_));
        }
        return xml::document_text(document);
    }

private:
    // Depth first, as MuJoCo numbers bodies and degrees of freedom: qvel follows the same order.
    void write_body(TiXmlElement* parent, int b, const Vec3& parent_origin, const Mat3& parent_axes) {
        const ExportBody& body = tree_.bodies[b];
        TiXmlElement* e = xml::child(parent, "body");
        e->SetAttribute("name", body.name);
        e->SetAttribute("pos", xml::xyz(Vec3(parent_axes.transpose() * (body.position - parent_origin))));
        const Vec4 quat = euler_parameters_from_rotation(parent_axes.transpose() * body.rotation);
        e->SetAttribute("quat", xml::numbers({quat[0], quat[1], quat[2], quat[3]}));
        TiXmlElement* inertial = xml::child(e, "inertial");
        inertial->SetAttribute("pos", "0 0 0");
        inertial->SetAttribute("mass", xml::number(body.mass));
        const Mat3& I = body.inertia;
        inertial->SetAttribute("fullinertia", xml::numbers({I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)}));
        for (const ExportJoint& joint : body.joints) write_joint(e, body, joint);
        for (int c : children_[b]) write_body(e, c, body.position, body.rotation);
    }

    void write_joint(TiXmlElement* body_element, const ExportBody& body, const ExportJoint& joint) {
        TiXmlElement* e = xml::child(body_element, "joint");
        e->SetAttribute("name", joint.name);
        e->SetAttribute("type", joint_type(joint.kind));
        if (joint.kind != ExportJointKind::Free) {
            e->SetAttribute("pos", xml::xyz(Vec3(body.rotation.transpose() * (joint.point - body.position))));
            if (joint.kind != ExportJointKind::Ball) e->SetAttribute("axis", xml::xyz(Vec3(body.rotation.transpose() * joint.axis)));
        }
        if (joint.stiffness != 0.0) {
            e->SetAttribute("stiffness", xml::number(joint.stiffness));
            e->SetAttribute("springref", xml::number(joint.spring_reference));
        }
        if (joint.damping != 0.0) e->SetAttribute("damping", xml::number(joint.damping));
        if (joint.armature != 0.0) e->SetAttribute("armature", xml::number(joint.armature));
        if (joint.has_lower || joint.has_upper) {  // a side without a limit: one never reached
            e->SetAttribute("limited", "true");
            e->SetAttribute("range", xml::numbers({joint.has_lower ? joint.lower : -kUnreachedLimit,
                                                   joint.has_upper ? joint.upper : kUnreachedLimit}));
        }
        qvel_.insert(qvel_.end(), joint.velocity.begin(), joint.velocity.end());
        if (!joint.spring_name.empty())
            body_element->LinkEndChild(new TiXmlComment((" spring-damper '" + joint.spring_name + "' ").c_str()));
        if (!joint.stop_name.empty())
            body_element->LinkEndChild(new TiXmlComment((" joint stop '" + joint.stop_name + "' ").c_str()));
    }

    const ExportTree& tree_;
    std::vector<int> roots_;
    std::map<int, std::vector<int>> children_;
    std::vector<double> qvel_;
};

}  // namespace

std::string mjcf_text(const ExportTree& tree) {
    return MjcfWriter(tree).text();
}

}  // namespace mbd::import
