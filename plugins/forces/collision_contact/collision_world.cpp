#include "collision_world.hpp"

#include <algorithm>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>

#include <cmath>
#include <cstdint>

namespace mbd::collision {

bool PairFilter::may_touch(int i, int j) const {
    const Shape& a = (*shapes_)[i];
    const Shape& b = (*shapes_)[j];
    if (a.body == b.body) return false;
    if (!(a.mask & b.group_bit) || !(b.mask & a.group_bit)) return false;
    return !joined_.count({std::min(a.body, b.body), std::max(a.body, b.body)});
}

namespace {

// FCL's convex polytope: its faces as [3, i, j, k, 3, ...]
std::shared_ptr<fcl::CollisionGeometryd> convex_of(const Mesh& mesh) {
    auto vertices = std::make_shared<std::vector<Vec3>>(mesh.vertices);
    auto faces = std::make_shared<std::vector<int>>();
    for (const auto& t : mesh.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
    return std::make_shared<fcl::Convexd>(vertices, static_cast<int>(mesh.triangles.size()), faces);
}

// A triangle soup in FCL's bounding-volume hierarchy (oriented and swept-sphere boxes)
std::shared_ptr<fcl::CollisionGeometryd> triangles_of(const Mesh& mesh) {
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Triangle> triangles;
    for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
    model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(mesh.vertices.size()));
    model->addSubModel(mesh.vertices, triangles);
    model->endModel();
    return model;
}

std::shared_ptr<fcl::CollisionGeometryd> geometry_of(const Shape& s) {
    switch (s.kind) {
        case ShapeKind::Sphere: return std::make_shared<fcl::Sphered>(s.radius);
        case ShapeKind::Capsule: return std::make_shared<fcl::Capsuled>(s.radius, s.length);
        case ShapeKind::Cylinder: return std::make_shared<fcl::Cylinderd>(s.radius, s.length);
        case ShapeKind::Box: return std::make_shared<fcl::Boxd>(s.size);
        case ShapeKind::Plane: return std::make_shared<fcl::Halfspaced>(Vec3::UnitZ(), 0.0);  // z <= 0 is solid
        case ShapeKind::ConvexMesh: return convex_of(*s.mesh);
        case ShapeKind::TriangleMesh: return triangles_of(*s.mesh);
    }
    return nullptr;
}

fcl::Transform3d pose(const Vec3& R, const Mat3& A, const Shape& s) {
    fcl::Transform3d t = fcl::Transform3d::Identity();
    t.linear() = A * s.rotation;
    t.translation() = R + A * s.position;
    return t;
}

int shape_of(const fcl::CollisionObjectd* o) { return static_cast<int>(reinterpret_cast<std::intptr_t>(o->getUserData())); }

// The points of a solid shape that can be its lowest against a plane of normal n (world), in
// world coordinates, with the radius to subtract from each point's height: a box's corners (FCL
// 0.7, boxHalfspaceIntersect, gives only the deepest corner, which cannot hold a box face resting
// on the plane); a capsule's two cap centres, each a sphere of its radius; a cylinder's lowest
// rim point on each end face (FCL gives one point, which cannot hold a cylinder on its side); a
// convex mesh's vertices (as a box's corners).
// A cylinder standing on an end face (its axis along n) is held at one rim point per face.
struct LowPoint {
    Vec3 point;
    double radius;
};

void low_points(const Shape& s, const fcl::Transform3d& T, const Vec3& n, std::vector<LowPoint>& out) {
    out.clear();
    switch (s.kind) {
        case ShapeKind::Box: {
            const Vec3 half = 0.5 * s.size;
            for (int corner = 0; corner < 8; ++corner)
                out.push_back({T * Vec3((corner & 1 ? 1 : -1) * half.x(), (corner & 2 ? 1 : -1) * half.y(),
                                        (corner & 4 ? 1 : -1) * half.z()),
                               0.0});
            return;
        }
        case ShapeKind::Capsule:
            for (double end : {-0.5, 0.5}) out.push_back({T * Vec3(0, 0, end * s.length), s.radius});
            return;
        case ShapeKind::Cylinder: {
            const Vec3 axis = T.linear().col(2);
            Vec3 down = -(n - n.dot(axis) * axis);  // downhill across the end faces
            if (down.norm() < 1e-12) down = T.linear().col(0);
            const Vec3 rim = s.radius * down.normalized();
            for (double end : {-0.5, 0.5}) out.push_back({T * Vec3(0, 0, end * s.length) + rim, 0.0});
            return;
        }
        case ShapeKind::ConvexMesh:
            for (const Vec3& v : s.mesh->vertices) out.push_back({T * v, 0.0});
            return;
        default: return;
    }
}

bool has_low_points(ShapeKind kind) {
    return kind == ShapeKind::Box || kind == ShapeKind::Capsule || kind == ShapeKind::Cylinder ||
           kind == ShapeKind::ConvexMesh;
}

}  // namespace

struct World::Detail {
    const std::vector<Shape>* shapes = nullptr;
    PairFilter filter;
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;  // one per shape
    std::vector<int> planes;                                      // shapes that are ground planes
    fcl::DynamicAABBTreeCollisionManagerd manager;                // every shape but the planes
    fcl::detail::GJKSolver_libccd<double> solver;
    fcl::CollisionRequestd request{8, true};  // up to 8 contacts a pair (a box face on a box: its corners)
    fcl::CollisionResultd result;
    std::vector<Contact> contacts;

    void narrow_phase(int i, int j);
    void solid_on_plane(int plane, int solid);
    void solid_on_triangles(int mesh, int solid);
    std::vector<LowPoint> low;  // solid_on_plane's and solid_on_triangles' workspace
    std::vector<int> triangles; // solid_on_triangles' workspace
    std::vector<bool> held;
    static bool on_candidate(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* self) {
        static_cast<Detail*>(self)->narrow_phase(shape_of(a), shape_of(b));
        return false;  // go on: every candidate pair
    }
};

// A solid shape against a plane: a contact at each of its low points below the plane, at its
// depth (exact), acting at its foot on the plane.
void World::Detail::solid_on_plane(int plane, int solid) {
    const fcl::Transform3d& P = objects[plane]->getTransform();
    const Vec3 n = P.linear().col(2);
    low_points((*shapes)[solid], objects[solid]->getTransform(), n, low);
    for (const LowPoint& p : low) {
        const double height = n.dot(p.point - P.translation()) - p.radius;
        if (height >= 0.0) continue;
        contacts.push_back({plane, solid, Vec3(p.point - (height + p.radius) * n), n, -height});
    }
}

// A solid shape against a triangle mesh: as against a plane, a contact at each of its low points
// below a triangle the solid overlaps (FCL's contacts name them), where the point's foot on the
// triangle's plane lies inside the triangle, along the triangle's outward normal. FCL itself gives
// one point per triangle, so a box face resting on the two triangles of a flat square was held at
// two points and rocked or fell through; its 4 corners hold it as a plane does. A low point is
// held by one triangle (the first that contains its foot: on a shared edge, not twice).
void World::Detail::solid_on_triangles(int mesh, int solid) {
    triangles.clear();
    for (size_t k = 0; k < result.numContacts(); ++k) {
        const fcl::Contactd& c = result.getContact(k);
        const int triangle = static_cast<int>(c.o1 == objects[mesh]->collisionGeometry().get() ? c.b1 : c.b2);
        if (std::find(triangles.begin(), triangles.end(), triangle) == triangles.end()) triangles.push_back(triangle);
    }
    const fcl::Transform3d& M = objects[mesh]->getTransform();
    const Mesh& m = *(*shapes)[mesh].mesh;
    held.assign(16, false);
    for (int t : triangles) {
        const Vec3 a = M * m.vertices[m.triangles[t][0]], b = M * m.vertices[m.triangles[t][1]],
                   c = M * m.vertices[m.triangles[t][2]];
        const Vec3 n = (b - a).cross(c - a).normalized();  // outward: counter-clockwise from outside
        low_points((*shapes)[solid], objects[solid]->getTransform(), n, low);
        if (held.size() < low.size()) held.resize(low.size(), false);
        for (size_t k = 0; k < low.size(); ++k) {
            const double height = n.dot(low[k].point - a) - low[k].radius;
            if (held[k] || height >= 0.0) continue;
            const Vec3 foot = low[k].point - (height + low[k].radius) * n;
            // inside the triangle: on the inner side of each edge
            if (n.dot((b - a).cross(foot - a)) < 0.0 || n.dot((c - b).cross(foot - b)) < 0.0 ||
                n.dot((a - c).cross(foot - c)) < 0.0)
                continue;
            held[k] = true;
            contacts.push_back(mesh < solid ? Contact{mesh, solid, foot, n, -height} : Contact{solid, mesh, foot, Vec3(-n), -height});
        }
    }
}

void World::Detail::narrow_phase(int i, int j) {
    if (!filter.may_touch(i, j)) return;
    const Shape& a = (*shapes)[i];
    const Shape& b = (*shapes)[j];
    if (a.kind == ShapeKind::Plane && has_low_points(b.kind)) return solid_on_plane(i, j);
    if (b.kind == ShapeKind::Plane && has_low_points(a.kind)) return solid_on_plane(j, i);
    result.clear();
    fcl::collide(objects[i].get(), objects[j].get(), &solver, request, result);
    if (a.kind == ShapeKind::TriangleMesh && has_low_points(b.kind)) return solid_on_triangles(i, j);
    if (b.kind == ShapeKind::TriangleMesh && has_low_points(a.kind)) return solid_on_triangles(j, i);
    const int plane = a.kind == ShapeKind::Plane ? i : b.kind == ShapeKind::Plane ? j : -1;
    // Against a triangle mesh FCL gives a contact per triangle the shape overlaps: a sphere on a
    // flat mesh near an edge would be pushed by its triangle's face and again, tilted, by the
    // neighbour's edge. The deepest contact alone is the face's (one point per pair).
    const bool deepest_only = a.kind == ShapeKind::TriangleMesh || b.kind == ShapeKind::TriangleMesh;
    const size_t first = contacts.size();
    for (size_t k = 0; k < result.numContacts(); ++k) {
        const fcl::Contactd& c = result.getContact(k);
        // FCL 0.7's triangle contacts: sphere/triangle gives minus the depth, and the normal
        // points from the mesh toward the shape whichever comes first; it is turned here to
        // point from the mesh toward the shape's centre, then from shape i to shape j
        const double depth = deepest_only ? std::abs(c.penetration_depth) : c.penetration_depth;
        // no force from a contact without a direction (EPA on a degenerate overlap can give a
        // zero or non-finite normal): a NaN would stop the run
        if (!(depth > 0.0) || !std::isfinite(depth) || !c.normal.allFinite() || !(c.normal.norm() > 0.5)) continue;
        Contact out{i, j, c.pos, c.normal.normalized(), depth};
        if (deepest_only) {
            const int shape = a.kind == ShapeKind::TriangleMesh ? j : i;
            if (out.normal.dot(objects[shape]->getTranslation() - out.point) < 0.0) out.normal = -out.normal;
            if (shape == i) out.normal = -out.normal;
        }
        if (plane >= 0) {
            // against a plane the force acts on the plane (as the sphere_plane element's does):
            // FCL's point is the middle of the overlap
            const fcl::Transform3d& P = objects[plane]->getTransform();
            const Vec3 n = P.linear().col(2);
            out.point -= n * n.dot(out.point - P.translation());
        }
        if (deepest_only && contacts.size() > first) {
            if (out.depth > contacts.back().depth) contacts.back() = out;
            continue;
        }
        contacts.push_back(out);
    }
}

World::World(const std::vector<Shape>& shapes, const PairFilter& filter) : detail_(std::make_unique<Detail>()) {
    Detail& d = *detail_;
    d.shapes = &shapes;
    d.filter = filter;
    std::vector<fcl::CollisionObjectd*> listed;
    for (size_t k = 0; k < shapes.size(); ++k) {
        d.objects.push_back(std::make_unique<fcl::CollisionObjectd>(geometry_of(shapes[k])));
        d.objects.back()->setUserData(reinterpret_cast<void*>(static_cast<std::intptr_t>(k)));
        if (shapes[k].kind == ShapeKind::Plane)
            d.planes.push_back(static_cast<int>(k));
        else
            listed.push_back(d.objects.back().get());
    }
    d.manager.registerObjects(listed);
    d.manager.setup();
}

World::~World() = default;

void World::place(int shape, const BodyStates& bodies) {
    Detail& d = *detail_;
    const Shape& s = (*d.shapes)[shape];
    const SpatialBody& b = bodies.spatial(s.body);
    d.objects[shape]->setTransform(pose(b.R, b.A, s));
    d.objects[shape]->computeAABB();
}

const std::vector<Contact>& World::detect_pair(int i, int j, const BodyStates& bodies) {
    Detail& d = *detail_;
    place(i, bodies);
    place(j, bodies);
    d.contacts.clear();
    d.narrow_phase(i, j);
    return d.contacts;
}

const std::vector<Contact>& World::detect(const BodyStates& bodies) {
    Detail& d = *detail_;
    for (size_t k = 0; k < d.objects.size(); ++k) place(static_cast<int>(k), bodies);
    d.manager.update();  // refit the tree to the new boxes
    d.contacts.clear();
    d.manager.collide(&d, &Detail::on_candidate);
    for (int plane : d.planes) d.manager.collide(d.objects[plane].get(), &d, &Detail::on_candidate);
    return d.contacts;
}

}  // namespace mbd::collision
