// The `visual:` key of a body (docs/scene-format.md, "visual"): shapes with a pose in
// the body frame, a scale and a colour. Errors name file:line and the key.
#include <mbd/visual.hpp>

#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/suggest.hpp>

#include <cctype>
#include <cmath>
#include <system_error>

namespace mbd {

const char* shape_kind_name(ShapeKind kind) {
    switch (kind) {
        case ShapeKind::Box: return "box";
        case ShapeKind::Cylinder: return "cylinder";
        case ShapeKind::Sphere: return "sphere";
        case ShapeKind::Capsule: return "capsule";
        case ShapeKind::Mesh: return "mesh";
    }
    return "?";
}

namespace {

const std::vector<std::string> kShapeNames{"box", "cylinder", "sphere", "capsule", "mesh"};

// The keys each shape accepts besides the pose and look keys.
std::vector<std::string> shape_keys(ShapeKind kind) {
    switch (kind) {
        case ShapeKind::Box: return {"size"};
        case ShapeKind::Cylinder:
        case ShapeKind::Capsule: return {"radius", "length"};
        case ShapeKind::Sphere: return {"radius"};
        case ShapeKind::Mesh: return {"file"};
    }
    return {};
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string hint(const std::string& word, const std::vector<std::string>& accepted) {
    const std::string best = nearest_name(word, accepted);
    if (!best.empty()) return "did you mean " + quote(best) + "?";
    std::string list;
    for (const auto& a : accepted) list += (list.empty() ? "" : ", ") + quote(a);
    return "accepted: " + list;
}

class ShapeReader {
public:
    ShapeReader(const Param& node, Dimension dimension, std::string what)
        : node_(node), planar_(dimension == Dimension::Planar), what_(std::move(what)) {}

    VisualShape read() {
        if (!node_.is_map())
            node_.fail(what_ + ": each 'visual' entry must be a map such as {shape: box, size: [0.4, 0.05, 0.05]}");
        const Param* shape = find("shape");
        if (!shape) node_.fail(what_ + ": a 'visual' entry needs 'shape' (one of box, cylinder, sphere, capsule, mesh)");
        if (!shape->is_scalar()) shape->fail(what_ + ": 'shape' must be one word (box, cylinder, sphere, capsule, mesh)");
        VisualShape s;
        s.where = node_.location();
        bool known = false;
        for (size_t k = 0; k < kShapeNames.size(); ++k)
            if (shape->text == kShapeNames[k]) {
                s.kind = static_cast<ShapeKind>(k);
                known = true;
            }
        if (!known)
            shape->fail(what_ + ": key 'shape': unknown shape " + quote(shape->text) + "; " +
                        hint(shape->text, kShapeNames));

        std::vector<std::string> accepted{"shape", "position", "rotation", "scale", "color"};
        for (const auto& k : shape_keys(s.kind)) accepted.push_back(k);
        for (const auto& [key, value] : node_.fields) {
            bool ok = false;
            for (const auto& a : accepted) ok = ok || a == key;
            if (!ok)
                value.fail(what_ + ": unknown key " + quote(key) + " in a " + shape->text + " visual; " +
                           hint(key, accepted));
        }

        switch (s.kind) {
            case ShapeKind::Box: {
                s.size = vector3(require("size", "[x, y, z] edge lengths in metres"), "size", false);
                for (int k = 0; k < 3; ++k)
                    if (!(s.size[k] > 0)) find("size")->fail(what_ + ": key 'size': every edge length must be positive");
                break;
            }
            case ShapeKind::Sphere: s.radius = positive("radius", "metres"); break;
            case ShapeKind::Cylinder:
            case ShapeKind::Capsule:
                s.radius = positive("radius", "metres");
                s.length = positive("length", s.kind == ShapeKind::Cylinder ? "height along the shape's z axis, metres"
                                                                            : "distance between the cap centres along "
                                                                              "the shape's z axis, metres");
                break;
            case ShapeKind::Mesh: s.mesh_file = mesh_path(require("file", "an STL, OBJ, DAE or glTF file, relative to the scene")); break;
        }
        if (const Param* p = find("position")) s.position = vector3(*p, "position", planar_);
        if (const Param* r = find("rotation")) s.rotation = rotation(*r);
        if (const Param* sc = find("scale")) {
            s.scale = sc->is_scalar() ? Vec3::Constant(number(*sc, "scale")) : vector3(*sc, "scale", false);
            for (int k = 0; k < 3; ++k)
                if (!(s.scale[k] > 0)) sc->fail(what_ + ": key 'scale': factors must be positive");
        }
        if (const Param* c = find("color")) s.color = color(*c);
        return s;
    }

private:
    const Param* find(const std::string& key) const {
        auto it = node_.fields.find(key);
        return it == node_.fields.end() ? nullptr : &it->second;
    }
    const Param& require(const std::string& key, const std::string& meaning) const {
        const Param* p = find(key);
        if (!p) node_.fail(what_ + ": a " + find("shape")->text + " visual needs " + quote(key) + " (" + meaning + ")");
        return *p;
    }

    double number(const Param& p, const std::string& key) const {
        if (!p.is_scalar()) p.fail(what_ + ": key " + quote(key) + " must be a number");
        try {
            size_t used = 0;
            const double v = std::stod(p.text, &used);
            if (used == p.text.size() && std::isfinite(v)) return v;
        } catch (const std::exception&) {
        }
        p.fail(what_ + ": key " + quote(key) + " must be a finite number, got " + quote(p.text));
    }
    double positive(const std::string& key, const std::string& meaning) const {
        const Param& p = require(key, meaning);
        const double v = number(p, key);
        if (!(v > 0)) p.fail(what_ + ": key " + quote(key) + " must be positive, got " + p.text);
        return v;
    }

    // Three numbers; a planar scene may give two (z = 0) where `allow_two`.
    Vec3 vector3(const Param& p, const std::string& key, bool allow_two) const {
        const bool size_ok = p.is_list() && (p.items.size() == 3 || (allow_two && p.items.size() == 2));
        if (!size_ok)
            p.fail(what_ + ": key " + quote(key) + " must be a list of " + (allow_two ? "2 or 3" : std::string("3")) +
                   " numbers [x, y" + (allow_two ? ", (z)]" : ", z]"));
        Vec3 v = Vec3::Zero();
        for (size_t k = 0; k < p.items.size(); ++k) v[k] = number(p.items[k], key);
        return v;
    }

    // {axis: [x, y, z], angle: radians}; planar scenes may give the angle alone (about z).
    Mat3 rotation(const Param& p) const {
        if (planar_ && p.is_scalar()) return rotation_from_euler_parameters(
            euler_parameters_from_axis_angle(Vec3::UnitZ(), number(p, "rotation")));
        if (!p.is_map())
            p.fail(what_ + ": key 'rotation' must be {axis: [x, y, z], angle: radians}" +
                   std::string(planar_ ? " or an angle about z" : ""));
        for (const auto& [key, value] : p.fields)
            if (key != "axis" && key != "angle")
                value.fail(what_ + ": unknown key " + quote(key) + " in 'rotation'; " + hint(key, {"axis", "angle"}));
        auto axis_it = p.fields.find("axis");
        auto angle_it = p.fields.find("angle");
        if (axis_it == p.fields.end() || angle_it == p.fields.end())
            p.fail(what_ + ": key 'rotation' needs both 'axis: [x, y, z]' and 'angle' (radians)");
        const Vec3 axis = vector3(axis_it->second, "axis", false);
        if (!(axis.norm() > 1e-12)) axis_it->second.fail(what_ + ": rotation 'axis' must not be the zero vector");
        return rotation_from_euler_parameters(euler_parameters_from_axis_angle(axis, number(angle_it->second, "angle")));
    }

    // [r, g, b] in [0, 1] or "#rrggbb".
    Vec3 color(const Param& p) const {
        if (p.is_scalar()) {
            const std::string& t = p.text;
            const bool hex = t.size() == 7 && t[0] == '#' &&
                             t.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos;
            if (!hex) p.fail(what_ + ": key 'color' must be [r, g, b] (each 0 to 1) or \"#rrggbb\", got " + quote(t));
            Vec3 c;
            for (int k = 0; k < 3; ++k) c[k] = std::stoi(t.substr(1 + 2 * k, 2), nullptr, 16) / 255.0;
            return c;
        }
        const Vec3 c = vector3(p, "color", false);
        for (int k = 0; k < 3; ++k)
            if (!(c[k] >= 0 && c[k] <= 1)) p.fail(what_ + ": key 'color': each of r, g, b must lie in [0, 1]");
        return c;
    }

    std::string mesh_path(const Param& p) const {
        if (!p.is_scalar() || p.text.empty()) p.fail(what_ + ": key 'file' must be the path of an STL, OBJ, DAE or glTF file");
        std::filesystem::path path(p.text);
        if (path.is_relative()) path = std::filesystem::path(node_.file).parent_path() / path;
        std::error_code error;
        const std::filesystem::file_status status = std::filesystem::status(path, error);
        if (std::filesystem::is_directory(status))
            p.fail(what_ + ": key 'file': " + quote(path.string()) + " is a folder; give the path of a mesh "
                   "file in it (the path is relative to the scene file's folder)");
        if (!std::filesystem::exists(status))
            p.fail(what_ + ": key 'file': mesh file " + quote(path.string()) +
                   " not found (the path is relative to the scene file's folder)");
        if (!std::filesystem::is_regular_file(status))
            p.fail(what_ + ": key 'file': " + quote(path.string()) + " is not a regular file (a device, FIFO or "
                   "socket); give the path of an STL, OBJ, DAE or glTF file");
        // The formats the viewer reads through Assimp (viewer/src/shape_mesh.cpp); the import's
        // list of drawable meshes is the same (import/src/mesh_file.cpp).
        std::string ext = path.extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (ext != ".stl" && ext != ".obj" && ext != ".dae" && ext != ".gltf" && ext != ".glb")
            p.fail(what_ + ": key 'file': " + quote(path.string()) +
                   " is not an .stl, .obj, .dae (Collada), .gltf or .glb file");
        return path.string();
    }

    const Param& node_;
    bool planar_;
    std::string what_;
};

}  // namespace

std::vector<VisualShape> parse_visual(const Param& node, Dimension dimension, const std::string& what) {
    std::vector<VisualShape> shapes;
    if (node.is_list()) {
        if (node.items.empty()) node.fail(what + ": 'visual' is an empty list; give at least one shape or remove the key");
        for (const auto& item : node.items) shapes.push_back(ShapeReader(item, dimension, what).read());
    } else {
        shapes.push_back(ShapeReader(node, dimension, what).read());
    }
    return shapes;
}

}  // namespace mbd
