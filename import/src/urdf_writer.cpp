// ExportTree -> URDF (model_writers.hpp). A URDF link's frame is its parent joint's frame, so
// each link's origin is its joint's anchor (the mass centre for fixed, floating and planar
// joints) with the body's axes, and its <inertial> is offset to the mass centre
// (docs/import.md, "Export").
#include <mbd/import/model_writers.hpp>

#include "xml_text.hpp"

#include <mbd/sdk/params.hpp>  // InputError
#include <mbd/sdk/text.hpp>

#include <cmath>

namespace mbd::import {

namespace {

// URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll). Pitch by atan2 (asin loses
// half the digits near +-pi/2, where robot files often are); roll from what yaw and pitch leave,
// which absorbs yaw's error there (the two turn about nearly the same axis).
Vec3 rpy(const Mat3& r) {
    const double pitch = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
    const double yaw = std::atan2(r(1, 0), r(0, 0));
    const Mat3 rest = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY())).toRotationMatrix().transpose() * r;
    return Vec3(std::atan2(rest(2, 1), rest(2, 2)), pitch, yaw);
}

bool planar_root(const ExportBody& body) { return body.joints.size() == 3; }  // slide x, slide y, hinge z

// The link's frame origin (world): the anchor of a hinge or slide, else the mass centre.
Vec3 link_origin(const ExportBody& body) {
    if (body.joints.size() == 1 && body.joints[0].kind != ExportJointKind::Free) return body.joints[0].point;
    return body.position;
}

class UrdfWriter {
public:
    UrdfWriter(const ExportTree& tree, std::vector<Unmapped>& left_out) : tree_(tree), left_out_(left_out) {}

    std::string text() {
        refuse_ball_joints();
        TiXmlDocument document;
        TiXmlElement* robot = xml::child(&document, "robot");
        robot->SetAttribute("name", tree_.name);
        std::string note = " Written by mbd export from " + tree_.source + " (docs/import.md). ";
        robot->LinkEndChild(new TiXmlComment(note.c_str()));
        xml::child(robot, "link")->SetAttribute("name", "world");
        for (size_t b = 0; b < tree_.bodies.size(); ++b) write_link(robot, static_cast<int>(b));
        list_left_out();
        return xml::document_text(document);
    }

private:
    void refuse_ball_joints() const {
        std::string names;
        for (const ExportBody& body : tree_.bodies)
            for (const ExportJoint& joint : body.joints)
                if (joint.kind == ExportJointKind::Ball) names += (names.empty() ? "'" : ", '") + joint.name + "'";
        if (!names.empty())
            throw InputError(tree_.source, "URDF has no ball joint: " + names + " (export MJCF instead: -o model.xml)");
    }

    void write_link(TiXmlElement* robot, int b) {
        const ExportBody& body = tree_.bodies[b];
        const Vec3 origin = link_origin(body);
        TiXmlElement* link = xml::child(robot, "link");
        link->SetAttribute("name", body.name);
        TiXmlElement* inertial = xml::child(link, "inertial");
        TiXmlElement* at = xml::child(inertial, "origin");
        at->SetAttribute("xyz", xml::xyz(Vec3(body.rotation.transpose() * (body.position - origin))));
        at->SetAttribute("rpy", "0 0 0");
        xml::child(inertial, "mass")->SetAttribute("value", xml::number(body.mass));
        TiXmlElement* inertia = xml::child(inertial, "inertia");
        const Mat3& I = body.inertia;
        const char* keys[] = {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"};
        const double values[] = {I(0, 0), I(0, 1), I(0, 2), I(1, 1), I(1, 2), I(2, 2)};
        for (int k = 0; k < 6; ++k) inertia->SetAttribute(keys[k], xml::number(values[k]));
        write_joint(robot, body, origin);
    }

    void write_joint(TiXmlElement* robot, const ExportBody& body, const Vec3& origin) {
        const bool root = body.parent < 0;
        const Vec3 parent_origin = root ? Vec3::Zero() : link_origin(tree_.bodies[body.parent]);
        const Mat3 parent_axes = root ? Mat3::Identity() : tree_.bodies[body.parent].rotation;
        TiXmlElement* joint = xml::child(robot, "joint");
        std::string type = "fixed", name = body.welded_by.empty() ? body.name + "_weld" : body.welded_by;
        if (planar_root(body)) type = "planar", name = body.name + "_planar";
        if (body.joints.size() == 1) {
            const ExportJoint& j = body.joints[0];
            name = j.name;
            const bool limited = j.has_lower || j.has_upper;
            type = j.kind == ExportJointKind::Hinge ? (limited ? "revolute" : "continuous")
                   : j.kind == ExportJointKind::Slide ? "prismatic" : "floating";
            if (j.stiffness != 0.0) springs_.push_back(j.spring_name);
            if (j.armature != 0.0) rotors_.push_back(j.rotor);
            for (double v : j.velocity) moving_ |= v != 0.0;
        }
        joint->SetAttribute("name", name);
        joint->SetAttribute("type", type);
        TiXmlElement* at = xml::child(joint, "origin");
        at->SetAttribute("xyz", xml::xyz(Vec3(parent_axes.transpose() * (origin - parent_origin))));
        at->SetAttribute("rpy", xml::xyz(rpy(parent_axes.transpose() * body.rotation)));
        xml::child(joint, "parent")->SetAttribute("link", root ? "world" : tree_.bodies[body.parent].name);
        xml::child(joint, "child")->SetAttribute("link", body.name);
        if (type == "continuous" || type == "revolute" || type == "prismatic" || type == "planar") {
            const Vec3 axis = type == "planar" ? Vec3::UnitZ() : body.joints[0].axis;
            xml::child(joint, "axis")->SetAttribute("xyz", xml::xyz(Vec3(body.rotation.transpose() * axis)));
        }
        if (type == "revolute" || type == "prismatic") {  // URDF requires them: a side without a stop never reached
            const ExportJoint& j = body.joints[0];
            TiXmlElement* limit = xml::child(joint, "limit");
            limit->SetAttribute("lower", xml::number(j.has_lower ? j.lower : -kUnreachedLimit));
            limit->SetAttribute("upper", xml::number(j.has_upper ? j.upper : kUnreachedLimit));
            limit->SetAttribute("effort", "0");
            limit->SetAttribute("velocity", "0");
        }
        if (body.joints.size() == 1 && body.joints[0].damping != 0.0)
            xml::child(joint, "dynamics")->SetAttribute("damping", xml::number(body.joints[0].damping));
        if (planar_root(body))
            for (const ExportJoint& j : body.joints) moving_ |= j.velocity[0] != 0.0;
    }

    void list_left_out() {
        if (!springs_.empty())
            left_out_.push_back({"joint springs in URDF", springs_, "URDF has damping but no stiffness; export MJCF to keep them"});
        if (!rotors_.empty())
            left_out_.push_back({"joint armatures (rotors) in URDF", rotors_, "URDF has no armature; export MJCF to keep them"});
        if (moving_)
            left_out_.push_back({"initial velocities in URDF", {tree_.name}, "URDF holds no initial state; the MJCF export keeps it"});
        if ((tree_.gravity - Vec3(0, 0, -9.81)).norm() > 1e-12)
            left_out_.push_back({"gravity in URDF", {"[" + format_number(tree_.gravity.x()) + ", " + format_number(tree_.gravity.y()) + ", " + format_number(tree_.gravity.z()) + "]"}, "URDF has no gravity; its tools assume 9.81 m/s^2 down -z"});
    }

    const ExportTree& tree_;
    std::vector<Unmapped>& left_out_;
    std::vector<std::string> springs_, rotors_;
    bool moving_ = false;
};

}  // namespace

std::string urdf_text(const ExportTree& tree, std::vector<Unmapped>& left_out) {
    return UrdfWriter(tree, left_out).text();
}

}  // namespace mbd::import
