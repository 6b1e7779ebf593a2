// Mesh collision shapes (issue 39; plugins/forces/collision_contact/collision_mesh.cpp): a
// `convex_mesh` on a body and a `triangle_mesh` on the ground, read from STL and OBJ files with
// Assimp, against independent oracles:
//  - a box given as a convex mesh pushes exactly as the box shape does, on a plane (the same
//    corners, each at its depth) and under a sphere (FCL's GJK/EPA for the mesh against its
//    analytic sphere/box, to EPA's tolerance);
//  - a sphere on a flat triangle mesh pushes exactly as on the plane through its top face,
//    also near the triangles' shared edge;
//  - a mesh that is not closed, or not convex, given as convex, and a triangle mesh on a body,
//    are refused naming the body.
#include "support/force_element_states.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using mbd::test::element;
using mbd::test::ElementStates;
using mbd::test::g17;
using Eigen::Vector3d;

// The corners of a box of edge lengths `size` centred on the origin: index x + 2y + 4z, each
// bit the + side along that axis.
std::array<Vector3d, 8> corners(const Vector3d& size) {
    std::array<Vector3d, 8> c;
    for (int k = 0; k < 8; ++k)
        c[k] = 0.5 * Vector3d((k & 1 ? 1 : -1) * size.x(), (k & 2 ? 1 : -1) * size.y(), (k & 4 ? 1 : -1) * size.z());
    return c;
}

// Its six faces, each counter-clockwise seen from outside (the cross product of the first two
// edges points out of the box).
const std::array<std::array<int, 4>, 6> kFaces = {{{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                                   {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};

std::string stl(const std::array<Vector3d, 8>& c, int faces = 6) {
    std::ostringstream out;
    out.precision(17);
    out << "solid box\n";
    for (int f = 0; f < faces; ++f)
        for (const auto& t : {std::array<int, 3>{kFaces[f][0], kFaces[f][1], kFaces[f][2]},
                              std::array<int, 3>{kFaces[f][0], kFaces[f][2], kFaces[f][3]}}) {
            out << " facet normal 0 0 0\n  outer loop\n";
            for (int v : t) out << "   vertex " << c[v].x() << " " << c[v].y() << " " << c[v].z() << "\n";
            out << "  endloop\n endfacet\n";
        }
    out << "endsolid box\n";
    return out.str();
}

// An OBJ of the box without its top face (+z): an open mesh.
std::string open_box_obj(const std::array<Vector3d, 8>& c) {
    std::ostringstream out;
    out.precision(17);
    for (const Vector3d& v : c) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (int f = 0; f < 6; ++f)
        if (f != 1) out << "f " << kFaces[f][0] + 1 << " " << kFaces[f][1] + 1 << " " << kFaces[f][2] + 1 << " "
                        << kFaces[f][3] + 1 << "\n";
    return out.str();
}

const std::string kLaw = "{stiffness: 1e7, exponent: 1.5, restitution: 0.6, impact_velocity: 1, static_friction: 0.4, "
                         "kinetic_friction: 0.3, stiction_velocity: 0.01}";

std::string box_body(const std::string& shape) {
    return "bodies:\n  - name: crate\n    mass: 2\n    inertia: [0.0083, 0.0283, 0.0333]\n"
           "    collision:\n      - " + shape + "\n";
}

// The generalized forces of an element on its last body at the state s (one spatial body).
Eigen::Matrix<double, 6, 1> force_on_body(const mbd::Model& model, const mbd::State& s) {
    const mbd::ForceInstance& f = element(model, "collision_contact");
    ElementStates states(f, s);
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(6 * static_cast<Eigen::Index>(f.bodies.size()));
    f.force->evaluate(states.view, Q);
    return Q.tail<6>();
}

// The largest relative difference of the contact force on the ball between two models of one
// scene, over `trials` states: the ball's mass centre from `centre(trial, u)` (u draws from
// [-1, 1]), upright, with velocities drawn from [-1, 1].
template <class Centre>
double worst_force_difference(const mbd::Model& a, const mbd::Model& b, int trials, unsigned seed, Centre centre) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> draw(-1.0, 1.0);
    const auto u = [&] { return draw(rng); };
    double worst = 0.0;
    for (int trial = 0; trial < trials; ++trial) {
        mbd::State s;
        s.q.resize(7);
        s.v.resize(6);
        const Vector3d c = centre(trial, u);
        s.q << c, 1, 0, 0, 0;
        for (int k = 0; k < 6; ++k) s.v[k] = u();
        const auto Qa = force_on_body(a, s), Qb = force_on_body(b, s);
        EXPECT_GT(Qa.norm(), 0.0) << "trial " << trial << ": no contact at " << c.transpose();
        worst = std::max(worst, (Qa - Qb).norm() / Qa.norm());
    }
    return worst;
}

// A 0.5 x 0.25 x 0.125 m box, turned and offset in its body, as the box shape and as a convex
// mesh (an STL) on a tilted plane: at random poses with corners below the plane, random
// velocities, the same corners push with the same law: the same forces to rounding. (Assimp
// reads vertices in single precision: these edge lengths are exact there.)
TEST(CollisionMesh, BoxAsConvexMeshOnAPlaneGivesTheBoxShapesForces) {
    const Vector3d size(0.5, 0.25, 0.125);
    const auto dir = mbd::test::scratch("collision_mesh_box");
    const auto file = mbd::test::write_text(dir / "box.stl", stl(corners(size)));
    const std::string pose = "position: [0.01, -0.02, 0.03], orientation: {axis: [1, 1, 0], angle: 0.3}, ";
    const std::string ground = "dimension: spatial\nground:\n  collision:\n    - {shape: plane, normal: [0.3, 0, 1], "
                               "material: {static_friction: 0.5}}\n";
    const mbd::Model as_box = mbd::test::scene(ground + box_body("{shape: box, size: [0.5, 0.25, 0.125], " + pose +
                                                                 "material: " + kLaw + "}"));
    const mbd::Model as_mesh = mbd::test::scene(ground + box_body("{shape: convex_mesh, file: " + file.string() +
                                                                  ", " + pose + "material: " + kLaw + "}"));
    const Vector3d n = Vector3d(0.3, 0, 1).normalized();
    const Eigen::Matrix3d shape_rotation = Eigen::AngleAxisd(0.3, Vector3d(1, 1, 0).normalized()).toRotationMatrix();
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0.0;
    int faces_touching = 0;  // poses with more than one corner below the plane
    for (int trial = 0; trial < 100; ++trial) {
        mbd::State s;
        s.q.resize(7);
        s.v.resize(6);
        // every other pose nearly face down on the plane (up to 4 corners below it)
        Eigen::Quaterniond turn(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
        if (trial % 2)
            turn = Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitZ(), n) *
                   Eigen::Quaterniond(Eigen::AngleAxisd(0.002 * u(rng), Vector3d(u(rng), u(rng), 0).normalized())) *
                   Eigen::Quaterniond(shape_rotation.transpose());
        const Eigen::Vector4d e(turn.w(), turn.x(), turn.y(), turn.z());
        const Eigen::Matrix3d A = mbd::rotation_from_euler_parameters(e);
        // the lowest corner 0 to 3 mm below the plane
        double lowest = 1e9;
        for (const Vector3d& c : corners(size))
            lowest = std::min(lowest, n.dot(A * (Vector3d(0.01, -0.02, 0.03) + shape_rotation * c)));
        const Vector3d lateral(u(rng), u(rng), u(rng));
        s.q.head<3>() = (-lowest - 0.0015 * (1 + u(rng))) * n + (lateral - lateral.dot(n) * n);
        s.q.segment<4>(3) = e;
        for (int k = 0; k < 6; ++k) s.v[k] = (trial % 3 == 0 ? 1e-3 : 1.0) * u(rng);
        const auto Qa = force_on_body(as_box, s), Qb = force_on_body(as_mesh, s);
        ASSERT_GT(Qa.norm(), 0.0) << "trial " << trial;
        EXPECT_LE((Qa - Qb).norm(), 1e-12 * Qa.norm()) << "trial " << trial;
        worst = std::max(worst, (Qa - Qb).norm() / Qa.norm());
        int below = 0;
        for (const Vector3d& c : corners(size))
            below += n.dot(s.q.head<3>() + A * (Vector3d(0.01, -0.02, 0.03) + shape_rotation * c)) < 0;
        faces_touching += below > 1;
    }
    EXPECT_GE(faces_touching, 40) << "half the poses rest on more than one corner";
    RecordProperty("worst_relative_difference", g17(worst));
}

// A sphere pressed into the top of a ground box, given as the box shape (FCL's analytic
// sphere/box) and as a convex mesh (GJK and EPA): the same force to EPA's tolerance. (The slab's
// edges are exact in single precision, as Assimp reads them.)
TEST(CollisionMesh, SphereOnABoxAsConvexMeshAgreesWithTheBoxShape) {
    const auto dir = mbd::test::scratch("collision_mesh_ground_box");
    const auto file = mbd::test::write_text(dir / "slab.stl", stl(corners(Vector3d(2, 2, 0.25))));
    const std::string ball = "bodies:\n  - name: ball\n    mass: 1\n    inertia: [0.004, 0.004, 0.004]\n"
                             "    collision:\n      - {shape: sphere, radius: 0.1, material: " + kLaw + "}\n";
    auto with_ground = [&](const std::string& shape) {
        return mbd::test::scene("dimension: spatial\nground:\n  collision:\n    - " + shape + "\n" + ball);
    };
    const mbd::Model as_box = with_ground("{shape: box, size: [2, 2, 0.25], position: [0, 0, -0.125], material: " + kLaw + "}");
    const mbd::Model as_mesh =
        with_ground("{shape: convex_mesh, file: " + file.string() + ", position: [0, 0, -0.125], material: " + kLaw + "}");
    const double worst = worst_force_difference(as_box, as_mesh, 50, 7, [](int, const auto& u) {
        return Vector3d(0.8 * u(), 0.8 * u(), 0.1 - 0.001 * (2 + u()));  // 1 to 3 mm deep
    });
    // GJK/EPA (libccd) finds the depth to 1e-6 m: with depths of 1 mm or more, F ~ delta^1.5
    // to 1.5e-3 relative (measured 3.7e-4)
    EXPECT_LT(worst, 1.5e-3);
    RecordProperty("worst_relative_difference", g17(worst));
}

// A sphere on a ground slab given as a triangle mesh (two triangles on its top face, split
// along x = y) pushes as on the plane z = 0: anywhere on the face, also within the contact
// patch's reach of the diagonal edge, where the neighbouring triangle's edge overlaps too.
TEST(CollisionMesh, SphereOnATriangleMeshPushesAsOnThePlaneOfItsFace) {
    const auto dir = mbd::test::scratch("collision_mesh_triangles");
    const auto file = mbd::test::write_text(dir / "slab.stl", stl(corners(Vector3d(2, 2, 0.25))));
    const std::string law = "{stiffness: 1e7, exponent: 1.5, restitution: 0.6, impact_velocity: 1, "
                            "static_friction: 0.4, kinetic_friction: 0.3, stiction_velocity: 0.01}";
    const std::string ball = "bodies:\n  - name: ball\n    mass: 1\n    inertia: [0.004, 0.004, 0.004]\n"
                             "    collision:\n      - {shape: sphere, radius: 0.1, material: " + law + "}\n";
    const mbd::Model on_plane = mbd::test::scene(
        "dimension: spatial\nground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1]}\n" + ball);
    const mbd::Model on_mesh = mbd::test::scene("dimension: spatial\nground:\n  collision:\n    - {shape: "
                                                "triangle_mesh, file: " + file.string() + ", position: [0, 0, -0.125]}\n" +
                                                ball);
    const double worst = worst_force_difference(on_plane, on_mesh, 100, 3, [](int trial, const auto& u) {
        const double along = 0.5 * u();
        const double across = trial % 2 ? 0.02 * u() : 0.4 * u();  // half of them by the diagonal
        return Vector3d(along + across, along - across, 0.1 - 0.002 * (1 + u()));
    });
    EXPECT_LE(worst, 1e-12);
    RecordProperty("worst_relative_difference", g17(worst));
}

TEST(CollisionMesh, OpenOrConcaveMeshesAsConvexAndTriangleMeshesOnBodiesAreRefusedNamingTheBody) {
    const auto dir = mbd::test::scratch("collision_mesh_bad");
    auto c = corners(Vector3d(0.4, 0.2, 0.1));
    const auto open = mbd::test::write_text(dir / "open.obj", open_box_obj(c));
    const auto closed = mbd::test::write_text(dir / "box.stl", stl(c));
    c[7].z() = 0.0;  // the top face folds along the diagonal 4-7 into a valley
    const auto dented = mbd::test::write_text(dir / "dented.stl", stl(c));
    const std::string ground = "dimension: spatial\nground:\n  collision:\n    - {shape: plane}\n";
    struct Case {
        std::string shape, says;
    };
    const std::vector<Case> cases = {
        {"{shape: convex_mesh, file: " + open.string() + ", material: " + kLaw + "}", "is not closed"},
        {"{shape: convex_mesh, file: " + dented.string() + ", material: " + kLaw + "}", "is not convex"},
        {"{shape: triangle_mesh, file: " + closed.string() + ", material: " + kLaw + "}", "a triangle_mesh is a ground shape"},
        {"{shape: convex_mesh, file: " + (dir / "missing.stl").string() + ", material: " + kLaw + "}", "not found"},
        {"{shape: convex_mesh, file: " + closed.string() + ", scale: 0, material: " + kLaw + "}", "'scale' factors must be positive"},
    };
    for (const Case& k : cases) {
        try {
            mbd::test::scene(ground + box_body(k.shape));
            ADD_FAILURE() << "accepted: " << k.shape;
        } catch (const mbd::InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(k.says), std::string::npos) << what;
            EXPECT_NE(what.find("body 'crate', collision shape 1"), std::string::npos) << what;
        }
    }
    // the closed box itself is accepted (the checks refuse only what they say)
    EXPECT_NO_THROW(mbd::test::scene(ground + box_body("{shape: convex_mesh, file: " + closed.string() +
                                                       ", material: " + kLaw + "}")));
}

}  // namespace

namespace {

// A box, slightly tilted in its body, on a ground slab given as a triangle mesh (its top face two
// triangles split along x = y) pushes as on the plane z = 0 of that face: at random places on the
// face (also across the diagonal) and random velocities, each corner below the face carries the
// plane's force, to rounding. FCL alone gives one point per triangle: at most two of the four
// corners, which let a box resting on a mesh rock or fall through it.
TEST(CollisionMesh, BoxOnATriangleMeshRestsOnItsCornersAsOnThePlaneOfItsFace) {
    const auto dir = mbd::test::scratch("collision_mesh_box_on_triangles");
    const auto file = mbd::test::write_text(dir / "slab.stl", stl(corners(Vector3d(2, 2, 0.25))));
    const std::string box = box_body("{shape: box, size: [0.5, 0.25, 0.125], orientation: {axis: [1, 2, 0], angle: 0.004}, "
                                     "material: " + kLaw + "}");
    const mbd::Model on_plane = mbd::test::scene(
        "dimension: spatial\nground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 0.5}}\n" + box);
    const mbd::Model on_mesh = mbd::test::scene("dimension: spatial\nground:\n  collision:\n    - {shape: triangle_mesh, "
                                                "file: " + file.string() + ", position: [0, 0, -0.125], "
                                                "material: {static_friction: 0.5}}\n" + box);
    const double worst = worst_force_difference(on_plane, on_mesh, 100, 11, [](int, const auto& u) {
        return Vector3d(0.6 * u(), 0.6 * u(), 0.0625 - 0.001 * (1.5 + u()));  // corners 0 to 3.5 mm deep
    });
    EXPECT_LE(worst, 1e-12);
    RecordProperty("worst_relative_difference", g17(worst));
}

}  // namespace
