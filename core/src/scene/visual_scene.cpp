// Shapes derived from the scene for bodies without `visual:` (docs/scene-format.md,
// "visual"): a link between each body's joint points, a small sphere at the mass
// centre, a short cylinder along each joint axis (a sphere for spherical joints),
// lines for springs and dampers, and a grid on the ground.
#include <mbd/model.hpp>
#include <mbd/visual.hpp>
#include <mbd/visual_joint_markers.hpp>

#include "scene/visual_wheels.hpp"

#include <mbd/sdk/rotation.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace mbd {
namespace {

// A body colour per index: distinct hues of equal lightness.
Vec3 body_color(int index) {
    static const Vec3 palette[] = {Vec3(0.20, 0.45, 0.80), Vec3(0.85, 0.35, 0.25), Vec3(0.25, 0.65, 0.35),
                                   Vec3(0.60, 0.40, 0.75), Vec3(0.90, 0.65, 0.15), Vec3(0.20, 0.65, 0.70)};
    return palette[index % 6];
}
const Vec3 kJointColor(0.22, 0.22, 0.25);
// The thinnest derived link, as a fraction of the mechanism's extent (the diagonal of its box
// at t = 0): at the default camera, which frames that box, about 4 pixels in a 750-pixel view.
constexpr double kMinThicknessOfExtent = 0.005;

// Rotation taking the z axis onto `direction` (unit).
Mat3 z_onto(const Vec3& direction) {
    const Vec3 z = direction.normalized();
    const Vec3 x = any_perpendicular(z).normalized();
    Mat3 a;
    a.col(0) = x;
    a.col(1) = z.cross(x);
    a.col(2) = z;
    return a;
}

VisualShape cylinder_between(const Vec3& a, const Vec3& b, double radius, const Vec3& color) {
    VisualShape s;
    s.kind = ShapeKind::Cylinder;
    s.radius = radius;
    s.length = (b - a).norm();
    s.position = 0.5 * (a + b);
    s.rotation = z_onto(b - a);
    s.color = color;
    return s;
}

VisualShape sphere_at(const Vec3& p, double radius, const Vec3& color) {
    VisualShape s;
    s.kind = ShapeKind::Sphere;
    s.radius = radius;
    s.position = p;
    s.color = color;
    return s;
}

void add_unique(std::vector<Vec3>& points, const Vec3& p) {
    for (const Vec3& q : points)
        if ((q - p).norm() < 1e-9) return;
    points.push_back(p);
}

bool is_connector_force(const std::string& type) { return type == "spring_damper"; }

// The uniform box with the body's mass and principal moments (a_k^2 = 6 / m (sum of the
// other two moments minus this one), from I_x = m (b^2 + c^2) / 12 and its permutations),
// posed along the principal axes; none when the moments give no real box.
bool inertia_box(const Body& body, VisualShape& box) {
    if (!(body.mass > 0)) return false;
    Eigen::SelfAdjointEigenSolver<Mat3> eig(body.inertia);
    const Vec3 I = eig.eigenvalues();
    Vec3 edges;
    for (int k = 0; k < 3; ++k) {
        const double sq = 6.0 / body.mass * (I.sum() - 2.0 * I[k]);
        if (!(sq > 0)) return false;
        edges[k] = std::sqrt(sq);
    }
    box.kind = ShapeKind::Box;
    box.size = edges;
    Mat3 axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    box.rotation = axes;
    return true;
}

// The size of the mechanism as placed at t = 0: the diagonal of the box around every mass
// centre and joint point (world).
double initial_extent(const Model& model, const std::vector<std::vector<Vec3>>& points) {
    Eigen::AlignedBox3d box;
    for (size_t b = 0; b < model.bodies.size(); ++b) {
        const Body& body = model.bodies[b];
        const Mat3 A = model.dimension == Dimension::Planar
                           ? (Mat3() << planar_rotation(body.angle), Vec2::Zero(), 0, 0, 1).finished()
                           : rotation_from_euler_parameters(body.euler_parameters);
        box.extend(body.position);
        for (const Vec3& p : points[b]) box.extend(body.position + A * p);
    }
    return box.isEmpty() ? 0.0 : box.diagonal().norm();
}

// Typical link size: the median over bodies of the largest distance between two of its
// attachment points, or with one point twice its distance from the mass centre (a frame
// carrying a rider far from its joints is as long as its joints are apart); with no joint
// points, the largest inertia box (spatial).
double typical_link_size(const Model& model, const std::vector<std::vector<Vec3>>& points) {
    std::vector<double> reach;
    for (const auto& pts : points) {
        double r = 0.0;
        for (const Vec3& p : pts) r = std::max(r, 2.0 * p.norm());
        if (pts.size() >= 2) {
            r = 0.0;
            for (const Vec3& p : pts)
                for (const Vec3& q : pts) r = std::max(r, (p - q).norm());
        }
        if (r > 0) reach.push_back(r);
    }
    double scale = 0.0;
    if (!reach.empty()) {
        std::nth_element(reach.begin(), reach.begin() + reach.size() / 2, reach.end());
        scale = reach[reach.size() / 2];
    } else {
        for (const Body& b : model.bodies) {
            VisualShape box;
            if (model.dimension != Dimension::Planar && inertia_box(b, box)) scale = std::max(scale, box.size.maxCoeff());
        }
    }
    return scale;
}

// The look of a body without `visual:`: its mass-centre sphere, its links, and its wheels, its
// rotor's disc or its inertia box.
struct DerivedLook {
    double link_radius, centre_radius;
    Vec3 color;
};

void add_derived_shapes(const Body& body, const std::vector<Vec3>& pts, const std::vector<DerivedWheel>& wheels,
                        bool planar, const DerivedLook& look, std::vector<VisualShape>& shapes) {
    const Vec3& color = look.color;
    double hub = look.centre_radius;  // inside a wheel's hub, not over its face
    for (const DerivedWheel& w : wheels) hub = std::min(hub, 0.25 * w.radius);
    shapes.push_back(sphere_at(Vec3::Zero(), hub, color));
    if (pts.size() == 2) {
        shapes.push_back(cylinder_between(pts[0], pts[1], look.link_radius, color));
    } else {
        for (const Vec3& p : pts)
            if (p.norm() > 1e-9) shapes.push_back(cylinder_between(p, Vec3::Zero(), look.link_radius, color));
    }
    VisualShape box;
    DerivedWheel rotor;
    if (!wheels.empty()) {  // a wheel: its contact radius, not its inertia's box
        for (const DerivedWheel& w : wheels) add_marked_wheel(shapes, w, look.link_radius, color);
    } else if (!planar && pts.size() < 2 && rotor_of_inertia(body, rotor)) {
        add_marked_wheel(shapes, rotor, look.link_radius, color);
    } else if (!planar && pts.size() < 2 && inertia_box(body, box)) {
        box.color = color;
        shapes.push_back(box);
    }
}

// A short cylinder along each joint axis (a sphere for a spherical joint): on the ground when
// the joint holds a body to it (a fixed pivot or guide), else on the joint's first body; a
// rolling contact's is the hub of its wheel, which rolls away from the point it touched at t = 0.
void add_joint_markers(const Model& model, double scale, double link_radius, const std::vector<DerivedWheel>& wheels,
                       VisualScene& scene, std::vector<JointMarkerShape>& markers) {
    const bool planar = model.dimension == Dimension::Planar;
    for (size_t j = 0; j < model.joints.size(); ++j) {
        const JointInstance& joint = model.joints[j];
        if (joint.bodies.empty() || joint.markers.size() != joint.bodies.size()) continue;
        const bool rolling = is_rolling_contact(joint.type);
        size_t on = 0;
        for (size_t k = 0; k < joint.bodies.size(); ++k)
            if (joint.bodies[k] == kGround && !rolling) on = k;
        if (joint.bodies[on] == kGround && rolling) on = joint.bodies.size() - 1;
        const Marker& m = joint.markers[on];
        VisualShape s;
        const auto wheel = std::find_if(wheels.begin(), wheels.end(),
                                        [&](const DerivedWheel& w) { return w.joint == static_cast<int>(j); });
        if (wheel != wheels.end()) {
            const double half = wheel_thickness(*wheel, link_radius);
            s = cylinder_between(wheel->centre - half * wheel->axis, wheel->centre + half * wheel->axis,
                                 0.12 * wheel->radius, kJointColor);
        } else if (joint.type == "spherical") {
            s = sphere_at(m.u_bar, 0.09 * scale, kJointColor);
        } else {
            Vec3 axis = m.axis_z();
            if (planar && (joint.type == "prismatic" || joint.type == "rack_pinion")) axis = m.axis_x();
            // planar pins stay behind the front of the mass-centre spheres (radius 0.1 scale)
            const double half = (joint.type == "prismatic" ? 0.6 : planar ? 0.07 : 0.18) * scale;
            s = cylinder_between(m.u_bar - half * axis, m.u_bar + half * axis,
                                 (joint.type == "prismatic" ? 0.6 : 1.6) * link_radius, kJointColor);
        }
        std::vector<VisualShape>& list = joint.bodies[on] == kGround ? scene.ground : scene.bodies[joint.bodies[on]];
        markers.push_back({static_cast<int>(j), joint.bodies[on], list.size()});
        list.push_back(s);
    }
}

}  // namespace

VisualScene build_visual_scene(const Model& model) {
    std::vector<JointMarkerShape> markers;
    return build_visual_scene(model, markers);
}

VisualScene build_visual_scene(const Model& model, std::vector<JointMarkerShape>& markers) {
    markers.clear();
    VisualScene scene;
    const bool planar = model.dimension == Dimension::Planar;
    const int nb = model.body_count();
    scene.bodies.resize(nb);
    if (model.gravity.norm() > 0)
        scene.up = -model.gravity.normalized();
    else
        scene.up = planar ? Vec3::UnitY() : Vec3::UnitZ();

    // joint points, in each body's frame; not a rolling contact's, which is a point of the rim
    // (or of the plane) that the wheel turns away from, not an attachment a link would join
    std::vector<std::vector<Vec3>> points(nb);
    for (const auto& joint : model.joints)
        if (!is_rolling_contact(joint.type))
            for (size_t k = 0; k < joint.bodies.size() && k < joint.markers.size(); ++k)
            if (joint.bodies[k] != kGround) add_unique(points[joint.bodies[k]], joint.markers[k].u_bar);

    double scale = typical_link_size(model, points);
    const double mechanism_size = initial_extent(model, points);
    if (!(scale > 0)) scale = 0.1;
    scene.length_scale = scale;
    // Links are at least a fraction of the whole mechanism thick: a chain of many short links
    // is drawn at its overall size, where links of 4 % of their own length would be hairlines.
    const double thickness = std::max(0.04 * scale, kMinThicknessOfExtent * mechanism_size);
    const double link_radius = thickness, centre_radius = std::max(0.1 * scale, 1.5 * thickness);
    const std::vector<DerivedWheel> rolling = rolling_contact_wheels(model);
    std::vector<std::vector<DerivedWheel>> wheels(nb);
    for (const DerivedWheel& w : rolling) wheels[w.body].push_back(w);

    for (int b = 0; b < nb; ++b) {
        const Body& body = model.bodies[b];
        if (!body.visuals.empty()) {
            scene.bodies[b] = body.visuals;
            continue;
        }
        add_derived_shapes(body, points[b], wheels[b], planar, {link_radius, centre_radius, body_color(b)},
                           scene.bodies[b]);
    }

    add_joint_markers(model, scale, link_radius, rolling, scene, markers);

    for (const auto& force : model.forces) {
        if (force.bodies.size() != 2 || force.markers.size() != 2 || !is_connector_force(force.type)) continue;
        VisualConnector c;
        c.name = force.name;
        c.body_a = force.bodies[0];
        c.body_b = force.bodies[1];
        c.point_a = force.markers[0].u_bar;
        c.point_b = force.markers[1].u_bar;
        c.radius = 0.5 * link_radius;
        scene.connectors.push_back(c);
    }

    // a grid fitted to the initial configuration; exporters refit it to the whole motion
    Eigen::AlignedBox3d extent;
    for (const Body& b : model.bodies) extent.extend(b.position);
    extent.extend(Vec3::Zero());
    fit_ground_grid(model, scene, extent);
    return scene;
}

// Planar scenes: a backdrop grid in the x-y plane, behind the mechanism. Spatial scenes:
// a grid across the up direction, under the lowest point of the motion.
void fit_ground_grid(const Model& model, VisualScene& scene, const Eigen::AlignedBox3d& extent) {
    const double margin = 0.5 * scene.length_scale;
    const Vec3 centre = extent.center();
    const double span = (extent.sizes().maxCoeff() + 2.0 * margin);
    // round to a whole number of grid steps of 1, 2 or 5 times a power of ten
    const double raw_step = span / 16.0;
    const double decade = std::pow(10.0, std::floor(std::log10(raw_step)));
    double step = decade;
    for (double f : {1.0, 2.0, 5.0, 10.0})
        if (f * decade >= raw_step) {
            step = f * decade;
            break;
        }
    scene.grid_divisions = static_cast<int>(std::ceil(span / step));
    scene.grid_size = scene.grid_divisions * step;
    if (model.dimension == Dimension::Planar) {
        scene.grid_centre = Vec3(std::round(centre.x() / step) * step, std::round(centre.y() / step) * step,
                                 -0.5 * scene.length_scale);
        scene.grid_normal = Vec3::UnitZ();
    } else {
        double lowest = 1e300;
        for (int k = 0; k < 8; ++k) lowest = std::min(lowest, extent.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)).dot(scene.up));
        const Vec3 in_plane = centre - centre.dot(scene.up) * scene.up;
        scene.grid_centre = in_plane + (lowest - 0.5 * scene.length_scale) * scene.up;
        scene.grid_normal = scene.up;
    }
}

}  // namespace mbd
