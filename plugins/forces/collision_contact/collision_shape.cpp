#include "collision_shape.hpp"

#include <mbd/sdk/text.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <map>

namespace mbd::collision {

namespace {

const std::map<std::string, ShapeKind>& kinds() {
    static const std::map<std::string, ShapeKind> k = {{"sphere", ShapeKind::Sphere},
                                                       {"capsule", ShapeKind::Capsule},
                                                       {"cylinder", ShapeKind::Cylinder},
                                                       {"box", ShapeKind::Box},
                                                       {"plane", ShapeKind::Plane},
                                                       {"convex_mesh", ShapeKind::ConvexMesh},
                                                       {"triangle_mesh", ShapeKind::TriangleMesh}};
    return k;
}

// The keys each kind takes besides `shape`, `material`, `group` and `collides_with`.
std::vector<std::string> size_keys(ShapeKind kind) {
    switch (kind) {
        case ShapeKind::Sphere: return {"radius", "position"};
        case ShapeKind::Capsule:
        case ShapeKind::Cylinder: return {"radius", "length", "position", "orientation"};
        case ShapeKind::Box: return {"size", "position", "orientation"};
        case ShapeKind::Plane: return {"normal", "point"};
        case ShapeKind::ConvexMesh:
        case ShapeKind::TriangleMesh: return {"file", "scale", "position", "orientation"};
    }
    return {};
}

double positive(const Param& shape, const std::string& key, const std::string& owner, const std::string& what) {
    const auto it = shape.fields.find(key);
    if (it == shape.fields.end()) shape.fail(owner + ": missing key '" + key + "' (" + what + ")");
    const double v = it->second.as_number(key, owner);
    if (!(v > 0.0))
        it->second.fail(owner + ": '" + key + "' must be positive (" + what + "), got " + it->second.text);
    return v;
}

Vec3 vector3(const Param& p, const std::string& key, const std::string& owner) {
    return p.as_vector(key, 3, owner);
}

// {axis: [x, y, z], angle: radians} in the body frame
Mat3 orientation(const Param& p, const std::string& owner) {
    if (!p.is_map() || !p.fields.count("axis") || !p.fields.count("angle") || p.fields.size() != 2)
        p.fail(owner + ": 'orientation' must be {axis: [x, y, z], angle: radians} in the body's frame");
    const Vec3 axis = vector3(p.fields.at("axis"), "axis", owner);
    if (!(axis.norm() > 1e-12)) p.fields.at("axis").fail(owner + ": orientation 'axis' must not be the zero vector");
    return Eigen::AngleAxisd(p.fields.at("angle").as_number("angle", owner), axis.normalized()).toRotationMatrix();
}

// The rotation whose z axis is the unit vector n.
Mat3 frame_of_normal(const Vec3& n) {
    return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), n).toRotationMatrix();
}

std::uint32_t group_bit(const Param& p, const std::string& owner) {
    return 1u << p.as_integer("group", 0, 31, owner);
}

constexpr const char* kKinds = "sphere, capsule, cylinder, box, plane, convex_mesh or triangle_mesh";

// `file` and `scale` (a number or [sx, sy, sz], each > 0) of a mesh shape.
std::shared_ptr<const Mesh> mesh_of(const Param& node, const Shape& s) {
    const auto file = node.fields.find("file");
    if (file == node.fields.end() || !file->second.is_scalar() || file->second.text.empty())
        node.fail(s.label + ": missing key 'file' (an STL or OBJ file, relative to the scene file's folder)");
    Vec3 scale = Vec3::Ones();
    if (const auto sc = node.fields.find("scale"); sc != node.fields.end()) {
        scale = sc->second.is_scalar() ? Vec3::Constant(sc->second.as_number("scale", s.label))
                                       : vector3(sc->second, "scale", s.label);
        if (!(scale.minCoeff() > 0.0)) sc->second.fail(s.label + ": 'scale' factors must be positive");
    }
    auto mesh = read_mesh(file->second, file->second.text, scale, s.label);
    if (s.kind == ShapeKind::ConvexMesh) check_convex(*mesh, file->second, file->second.text, s.label);
    return mesh;
}

// The keys that size a shape of its kind (radius, length, size, the plane's normal and point,
// a mesh's file); `type` is the node of its `shape` key.
void read_dimensions(const Param& node, const Param& type, Shape& s, bool ground) {
    switch (s.kind) {
        case ShapeKind::Sphere: s.radius = positive(node, "radius", s.label, "the sphere's radius, m"); break;
        case ShapeKind::Capsule:
        case ShapeKind::Cylinder:
            s.radius = positive(node, "radius", s.label, "m");
            s.length = positive(node, "length", s.label,
                                s.kind == ShapeKind::Capsule ? "between the centres of its end caps, along its z axis, m"
                                                             : "end to end, along its z axis, m");
            break;
        case ShapeKind::Box: {
            if (!node.fields.count("size")) node.fail(s.label + ": missing key 'size' ([lx, ly, lz], the edge lengths, m)");
            const Param& size = node.fields.at("size");
            s.size = vector3(size, "size", s.label);
            for (int k = 0; k < 3; ++k)
                if (!(s.size[k] > 0.0))
                    size.items[k].fail(s.label + ": 'size' entries must be positive (the edge lengths, m), got " +
                                       size.items[k].text);
            break;
        }
        case ShapeKind::Plane: {
            if (!ground)
                type.fail(s.label + ": a plane (a half-space) is a ground shape; give it under "
                                            "'ground: {collision: [...]}', or use a box on a body");
            const Vec3 n = node.fields.count("normal") ? vector3(node.fields.at("normal"), "normal", s.label)
                                                       : Vec3::UnitZ();
            if (!(n.norm() > 1e-12))
                node.fields.at("normal").fail(s.label + ": 'normal' must not be the zero vector (it points out of "
                                                        "the ground, into the space where bodies move)");
            s.rotation = frame_of_normal(n.normalized());
            if (node.fields.count("point")) s.position = vector3(node.fields.at("point"), "point", s.label);
            break;
        }
        case ShapeKind::TriangleMesh:
            if (!ground)
                type.fail(s.label + ": a triangle_mesh is a ground shape (static, touched by the bodies' "
                                            "other shapes); give it under 'ground: {collision: [...]}', or give a "
                                            "body a convex_mesh");
            s.mesh = mesh_of(node, s);
            break;
        case ShapeKind::ConvexMesh: s.mesh = mesh_of(node, s); break;
    }
}

Shape read_shape(const Param& node, const std::string& owner, bool ground) {
    if (!node.is_map()) node.fail(owner + " must be a map of keys (shape, radius or size, material, ...)");
    const auto type = node.fields.find("shape");
    if (type == node.fields.end())
        node.fail(owner + ": missing key 'shape' (" + kKinds + ")");
    const auto kind = kinds().find(type->second.text);
    if (!type->second.is_scalar() || kind == kinds().end())
        type->second.fail(owner + ": 'shape' must be " + kKinds + ", got '" +
                          type->second.text + "'");
    Shape s;
    s.kind = kind->second;
    s.label = owner + " (" + kind->first + ")";
    s.where = node.location();
    std::vector<std::string> accepted = size_keys(s.kind);
    accepted.insert(accepted.end(), {"shape", "material", "group", "collides_with"});
    for (const auto& kv : node.fields)
        if (std::find(accepted.begin(), accepted.end(), kv.first) == accepted.end())
            kv.second.fail(s.label + ": unknown key '" + kv.first + "'; a " + kind->first + " takes " +
                           [&] {
                               std::string list;
                               for (const auto& k : accepted) list += (list.empty() ? "" : ", ") + k;
                               return list;
                           }());
    read_dimensions(node, type->second, s, ground);
    if (node.fields.count("position")) s.position = vector3(node.fields.at("position"), "position", s.label);
    if (node.fields.count("orientation")) s.rotation = orientation(node.fields.at("orientation"), s.label);
    if (node.fields.count("group")) s.group_bit = group_bit(node.fields.at("group"), s.label);
    if (node.fields.count("collides_with")) {
        const Param& with = node.fields.at("collides_with");
        if (!with.is_list())
            with.fail(s.label + ": 'collides_with' must be a list of groups (whole numbers 0 to 31)");
        s.mask = 0;
        for (const Param& g : with.items) s.mask |= group_bit(g, s.label);
    }
    if (node.fields.count("material")) {
        s.material = read_material(node.fields.at("material"), s.label, ground);
    } else if (ground) {
        s.material.rigid = true;  // a rigid, frictionless ground: the other shape's law acts
    } else {
        node.fail(s.label + ": missing key 'material' (stiffness, exponent, restitution, friction, ...)");
    }
    if (s.material.hertz && s.kind != ShapeKind::Sphere && s.kind != ShapeKind::Capsule)
        node.fields.at("material").fail(s.label + ": 'young_modulus' gives Hertz's law of a curved surface (spheres "
                                                  "and capsules); give a " + kind->first + " a 'stiffness' and "
                                                  "'exponent'");
    return s;
}

}  // namespace

double curvature_radius(const Shape& s) {
    return s.kind == ShapeKind::Sphere || s.kind == ShapeKind::Capsule ? s.radius
                                                                        : std::numeric_limits<double>::infinity();
}

const char* kind_name(ShapeKind kind) {
    for (const auto& [name, k] : kinds())
        if (k == kind) return name.c_str();
    return "?";
}

std::vector<Shape> read_shapes(const Param& list, const std::string& body_name, int body, bool ground, bool massless) {
    const std::string owner = ground ? std::string("the ground") : "body '" + body_name + "'";
    if (!list.is_list() || list.items.empty())
        list.fail(owner + ": 'collision' must be a list of shapes, e.g. [{shape: sphere, radius: 0.1, material: "
                          "{stiffness: 1e7}}]");
    if (massless)
        list.fail(owner + " has collision shapes but no mass: a contact force on a massless body has no "
                          "acceleration to act on; give the body its mass and inertia, or remove 'collision'");
    std::vector<Shape> shapes;
    for (size_t k = 0; k < list.items.size(); ++k) {
        shapes.push_back(read_shape(list.items[k], owner + ", collision shape " + std::to_string(k + 1), ground));
        shapes.back().body = body;
    }
    return shapes;
}

}  // namespace mbd::collision
