// The topology of a System's joint graph (nodes: the bodies and the ground; edges: the
// joints): whether it is a tree (no closed loops), which joints close loops (cut
// joints), and a parent-first order of the bodies. Recursive (relative-coordinate)
// formulations use it to decide whether a scene can be written in joint coordinates
// (book Sec. 4.5 and the joint-constraint notes Sec. 5 on RelativeMotion); `mbd check`
// prints the same decision. Header-only, over the SDK's System.
#pragma once

#include <mbd/kit/system.hpp>

#include <cmath>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

namespace mbd {

struct Topology {
    int bodies = 0;
    bool tree = true;                   // no joint closes a loop
    bool relative = true;               // every joint describes its relative motion (RelativeMotion)
    std::vector<int> cut_joints;        // joints that close a loop (scene order: the later joint of each loop)
    std::vector<int> other_joints;      // joints that cannot be tree edges (not two-body, or refused by the caller)
    std::vector<int> parent_joint;      // per body: the tree joint towards the ground (-1: a free root)
    std::vector<int> parent_body;       // per body: the parent body (-1: the ground or none)
    std::vector<int> order;             // bodies, every parent before its children
    int free_roots = 0;                 // bodies (subtrees) connected to nothing fixed
};

namespace topology_detail {
inline int find(std::vector<int>& p, int x) {
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
}
}  // namespace topology_detail

// The spanning tree in scene order; `tree_edge(j)` says whether joint j may be a tree edge
// (a joint it refuses is listed in other_joints and leaves its rows to the closure).
template <class TreeEdge>
Topology analyse_topology(const System& system, TreeEdge&& tree_edge) {
    Topology t;
    const int nb = system.body_count();
    t.bodies = nb;
    const int ground = nb;  // the ground is one node
    std::vector<int> uf(nb + 1);
    std::iota(uf.begin(), uf.end(), 0);
    std::vector<std::vector<int>> adjacent(nb + 1);  // joint indices
    for (int j = 0; j < system.joint_count(); ++j) {
        const JointInfo& info = system.joint(j);
        if (!info.joint || !info.joint->relative_motion()) t.relative = false;
        if (info.bodies.size() != 2 || !tree_edge(j)) {
            t.other_joints.push_back(j);
            t.tree = false;
            continue;
        }
        const int a = info.bodies[0] < 0 ? ground : info.bodies[0];
        const int b = info.bodies[1] < 0 ? ground : info.bodies[1];
        const int ra = topology_detail::find(uf, a), rb = topology_detail::find(uf, b);
        if (ra == rb) {
            t.cut_joints.push_back(j);
            t.tree = false;
            continue;
        }
        uf[ra] = rb;
        adjacent[a].push_back(j);
        adjacent[b].push_back(j);
    }
    // parent-first order: from the ground, then from each body not reached (a free root)
    t.parent_joint.assign(nb, -1);
    t.parent_body.assign(nb, -1);
    std::vector<char> seen(nb + 1, 0);
    auto visit = [&](int start) {
        std::vector<int> queue{start};
        seen[start] = 1;
        for (size_t k = 0; k < queue.size(); ++k) {
            const int node = queue[k];
            if (node != ground) t.order.push_back(node);
            for (int j : adjacent[node]) {
                const JointInfo& info = system.joint(j);
                const int a = info.bodies[0] < 0 ? ground : info.bodies[0];
                const int b = info.bodies[1] < 0 ? ground : info.bodies[1];
                const int other = a == node ? b : a;
                if (seen[other]) continue;
                seen[other] = 1;
                t.parent_joint[other] = j;
                t.parent_body[other] = node == ground ? -1 : node;
                queue.push_back(other);
            }
        }
    };
    visit(ground);
    for (int b = 0; b < nb; ++b)
        if (!seen[b]) {
            ++t.free_roots;
            visit(b);
        }
    return t;
}

inline Topology analyse_topology(const System& system) {
    return analyse_topology(system, [](int) { return true; });
}

// Whether a joint's relative motion can be a tree edge of the recursive embedding
// path: at most two rotations (revolute or helical) and any translations, or one ball
// and translations; planar scenes: rotations about z and translations in the plane.
inline bool recursive_motion_supported(const RelativeMotion& m, Dimension dimension) {
    int rotations = 0, balls = 0;
    for (const RelativeMotion::Freedom& f : m.freedoms) {
        if (f.kind == RelativeMotion::Kind::Ball) ++balls;
        if (f.kind == RelativeMotion::Kind::Revolute || f.kind == RelativeMotion::Kind::Helical) ++rotations;
        if (dimension == Dimension::Planar) {
            const bool rot = f.kind != RelativeMotion::Kind::Prismatic;
            if (f.kind == RelativeMotion::Kind::Ball || f.kind == RelativeMotion::Kind::Helical) return false;
            if (rot && std::abs(std::abs(f.axis.z()) - 1.0) > 1e-12) return false;
            if (!rot && std::abs(f.axis.z()) > 1e-12) return false;
        }
    }
    if (dimension == Dimension::Planar && rotations > 1) return false;
    // two rotations must be about different axes (the decomposition of a relative pose)
    if (balls == 0 && rotations == 2) {
        Vec3 axes[2];
        int k = 0;
        for (const RelativeMotion::Freedom& f : m.freedoms)
            if (f.kind != RelativeMotion::Kind::Prismatic) axes[k++] = f.axis.normalized();
        if (axes[0].cross(axes[1]).norm() < 1e-6) return false;
    }
    return balls == 0 ? rotations <= 2 : (balls == 1 && rotations == 0);
}

// The embedding formulation's choice for a system: "recursive" when the joints form a
// tree, every joint gives a supported relative motion and every driver drives a joint of one
// freedom (revolute, prismatic or helical: its motion is then prescribed, not a constraint
// row); else "closure" or "dense". `reason` says why (for messages and `mbd check`).
inline bool recursive_embedding_possible(const System& system, std::string* reason = nullptr) {
    const Topology t = analyse_topology(system);
    auto say = [&](const std::string& s) {
        if (reason) *reason = s;
    };
    if (!t.tree) {
        std::string names;
        for (int j : t.cut_joints) names += (names.empty() ? "'" : ", '") + system.joint(j).name + "'";
        for (int j : t.other_joints) names += (names.empty() ? "'" : ", '") + system.joint(j).name + "'";
        say(std::to_string(t.cut_joints.size()) + " closed loop" + (t.cut_joints.size() == 1 ? "" : "s") +
            " (cut joint" + (t.cut_joints.size() + t.other_joints.size() == 1 ? " " : "s ") + names + ")");
        return false;
    }
    std::vector<int> drivers_of_joint(system.joint_count(), 0);
    for (int d = 0; d < system.driver_count(); ++d) ++drivers_of_joint.at(system.driver(d).joint);
    for (int j = 0; j < system.joint_count(); ++j) {
        const auto motion = system.joint(j).joint->relative_motion();
        if (!motion) {
            say("joint '" + system.joint(j).name + "' (" + system.joint(j).type + ") has no relative-coordinate description");
            return false;
        }
        if (!recursive_motion_supported(*motion, system.dimension())) {
            say("joint '" + system.joint(j).name + "' (" + system.joint(j).type +
                ") has a relative motion the recursive path does not support");
            return false;
        }
        if (drivers_of_joint[j] > 1) {
            say("joint '" + system.joint(j).name + "' has " + std::to_string(drivers_of_joint[j]) + " drivers");
            return false;
        }
        const bool one_freedom =
            motion->freedoms.size() == 1 && motion->freedoms.front().kind != RelativeMotion::Kind::Ball;
        if (drivers_of_joint[j] == 1 && !one_freedom) {
            say("driven joint '" + system.joint(j).name + "' (" + system.joint(j).type +
                ") has a relative motion of more than one freedom");
            return false;
        }
    }
    const int driven = system.driver_count();
    say("tree of " + std::to_string(system.joint_count()) + " joint" + (system.joint_count() == 1 ? "" : "s") +
        (t.free_roots ? " and " + std::to_string(t.free_roots) + " free root body" + (t.free_roots == 1 ? "" : "s") : "") +
        " in joint coordinates" +
        (driven ? ", " + std::to_string(driven) + " of them driven (prescribed motion)" : std::string()));
    return true;
}

// The spanning tree of the joint-coordinate path with closure rows: only joints whose relative
// motion the recursive path supports are tree edges, preferred in scene order; every other
// joint (a cut joint, a joint without a supported relative motion) keeps its rows.
inline Topology analyse_closure_topology(const System& system) {
    return analyse_topology(system, [&](int j) {
        const auto motion = system.joint(j).joint ? system.joint(j).joint->relative_motion() : std::nullopt;
        return motion && recursive_motion_supported(*motion, system.dimension());
    });
}

// The embedding formulation's second recursive choice (issue 13): a spanning tree in joint
// coordinates plus the rows of the other joints and of the drivers as loop-closure rows
// (plugins/formulations/articulated_body/loop_closure.hpp). Possible when no joint has velocity-level
// rows and at least one joint is a tree edge (else nothing would be eliminated); `reason` says
// which joints close the loops.
inline bool closure_embedding_possible(const System& system, std::string* reason = nullptr) {
    const Topology t = analyse_closure_topology(system);
    auto say = [&](const std::string& s) {
        if (reason) *reason = s;
    };
    const int nonholonomic = system.first_nonholonomic_joint();
    if (nonholonomic >= 0) {
        say("joint '" + system.joint(nonholonomic).name + "' has velocity-level rows");
        return false;
    }
    const int tree_joints = system.joint_count() - static_cast<int>(t.cut_joints.size() + t.other_joints.size());
    if (tree_joints == 0) {
        say("no joint can be a tree edge in joint coordinates");
        return false;
    }
    std::string names;
    for (const auto* list : {&t.cut_joints, &t.other_joints})
        for (int j : *list) names += (names.empty() ? "'" : ", '") + system.joint(j).name + "'";
    const int closing = static_cast<int>(t.cut_joints.size() + t.other_joints.size());
    say("tree of " + std::to_string(tree_joints) + " joint" + (tree_joints == 1 ? "" : "s") +
        (t.free_roots ? " and " + std::to_string(t.free_roots) + " free root body" + (t.free_roots == 1 ? "" : "s") : "") +
        " in joint coordinates closed by " +
        (closing ? std::to_string(closing) + " joint" + (closing == 1 ? " " : "s ") + names : std::string()) +
        (closing && system.driver_count() ? " and " : "") +
        (system.driver_count() ? std::to_string(system.driver_count()) + " driver" + (system.driver_count() == 1 ? "" : "s")
                               : std::string()) +
        " (constraint rows)");
    return true;
}

}  // namespace mbd
