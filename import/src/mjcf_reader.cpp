// mjModel -> SourceTree (mjcf_reader.hpp). Every quantity is read from the compiled model, so
// MuJoCo's defaults and frame conventions apply exactly (docs/import.md, "MJCF").
#include <mbd/import/mjcf_reader.hpp>

#include <mbd/import/mjcf_compile.hpp>

#include <mbd/sdk/params.hpp>  // InputError
#include <mbd/sdk/text.hpp>

#include <mujoco/mujoco.h>

#include <algorithm>
#include <memory>
#include <string>

namespace mbd::import {

namespace {

std::string name_of(const mjModel* m, int type, int id, const char* kind) {
    const char* name = mj_id2name(m, type, id);
    return (name && *name) ? std::string(name) : std::string(kind) + " #" + std::to_string(id);
}

Vec3 vec(const mjtNum* v) { return Vec3(v[0], v[1], v[2]); }

Mat3 mat(const mjtNum* v) {  // MuJoCo's 3x3 matrices are row-major
    Mat3 a;
    a << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
    return a;
}

Mat3 quat(const mjtNum* q) { return rotation_from_euler_parameters(Vec4(q[0], q[1], q[2], q[3]).normalized()); }

// MuJoCo's limits are soft (solref/solimp: a spring-damper whose stiffness scales with the joint's
// effective inertia); mbd's joint_stop is a stiff stop as for a hard URDF limit (docs/import.md).
constexpr double kMjcfLimitStiffness = 1e8;

SourceJoint joint(const mjModel* m, const mjData* d, int j, const std::string& file) {
    SourceJoint out;
    out.name = name_of(m, mjOBJ_JOINT, j, "joint");
    out.where = file;
    switch (m->jnt_type[j]) {
        case mjJNT_HINGE: out.kind = SourceJointKind::Hinge; break;
        case mjJNT_SLIDE: out.kind = SourceJointKind::Slide; break;
        case mjJNT_BALL: out.kind = SourceJointKind::Ball; break;
        default: out.kind = SourceJointKind::Free; break;
    }
    out.point = vec(d->xanchor + 3 * j);
    out.axis = vec(d->xaxis + 3 * j);
    if (out.kind == SourceJointKind::Hinge || out.kind == SourceJointKind::Slide) {
        const int q = m->jnt_qposadr[j];
        out.stiffness = m->jnt_stiffness[j];
        out.spring_reference = m->qpos_spring[q] - m->qpos0[q];  // mbd's angle is zero at qpos0
        out.damping = m->dof_damping[m->jnt_dofadr[j]];
        out.armature = m->dof_armature[m->jnt_dofadr[j]];
        if (m->jnt_limited[j]) {  // range in qpos units; mbd's coordinate is zero at qpos0
            out.limited = true;
            out.lower = m->jnt_range[2 * j] - m->qpos0[q];
            out.upper = m->jnt_range[2 * j + 1] - m->qpos0[q];
            out.stop_stiffness = kMjcfLimitStiffness;
        }
    }
    return out;
}

// An equality `joint`: MuJoCo holds q1 - q1_0 = a0 + a1 (q2 - q2_0) + a2 (q2 - q2_0)^2 + ... (polycoef a0..a4,
// q_0 = qpos0): the linear part is a coordinate_coupling; a curved one is refused, not approximated.
SourceCoupling joint_coupling(const mjModel* m, int e, const std::string& name, const std::string& file) {
    const mjtNum* poly = m->eq_data + mjNEQDATA * e;
    SourceCoupling c;
    c.name = name;
    c.where = file;
    c.what = "MJCF equality joint '" + name + "'";
    c.follower = name_of(m, mjOBJ_JOINT, m->eq_obj1id[e], "joint");
    c.leader = name_of(m, mjOBJ_JOINT, m->eq_obj2id[e], "joint");
    c.offset = poly[0];
    c.multiplier = poly[1];
    if (poly[2] != 0.0 || poly[3] != 0.0 || poly[4] != 0.0)
        throw InputError(file, c.what + ": its polycoef has non-zero terms of degree 2 to 4 (" + format_number(poly[2]) + " " +
                                   format_number(poly[3]) + " " + format_number(poly[4]) +
                                   "); mbd couples joints linearly only (coordinate_coupling): give polycoef \"" +
                                   format_number(poly[0]) + " " + format_number(poly[1]) + " 0 0 0\" or remove the equality");
    return c;
}

// MuJoCo's equality constraints that close loops: `connect` as a ball joint at its anchor, `weld`
// as a fixed joint (in the relative pose at qpos0, which must be its relpose). Returns the names
// of those not mapped (joint and tendon couplings, inactive ones).
std::vector<std::string> read_equalities(const mjModel* m, const mjData* d, SourceTree& tree) {
    std::vector<std::string> left;
    for (int e = 0; e < m->neq; ++e) {
        const std::string name = name_of(m, mjOBJ_EQUALITY, e, "equality");
        const int type = m->eq_type[e];
        if (m->eq_active[e] && type == mjEQ_JOINT && m->eq_obj2id[e] >= 0) {
            tree.couplings.push_back(joint_coupling(m, e, name, tree.file));
            continue;
        }
        if (!m->eq_active[e] || (type != mjEQ_CONNECT && type != mjEQ_WELD)) {
            left.push_back(name + (m->eq_active[e] ? "" : " (inactive)"));
            continue;
        }
        const int b1 = m->eq_obj1id[e], b2 = m->eq_obj2id[e];
        const mjtNum* data = m->eq_data + mjNEQDATA * e;
        SourceLoop loop;
        loop.joint.name = name;
        loop.joint.where = tree.file;
        loop.joint.kind = SourceJointKind::Ball;
        loop.body_a = b1 - 1;  // body 0 is the world
        loop.body_b = b2 - 1;
        const Mat3 r1 = mat(d->xmat + 9 * b1), r2 = mat(d->xmat + 9 * b2);
        if (type == mjEQ_CONNECT) {  // anchor in body1's frame; body2's point is where it lies at qpos0
            loop.joint.point = vec(d->xpos + 3 * b1) + r1 * vec(data);
        } else {  // anchor in body2's frame, then relpose: body2's frame in body1's
            loop.weld = true;
            loop.joint.point = vec(d->xpos + 3 * b2) + r2 * vec(data);
            const Vec3 at = r1.transpose() * (vec(d->xpos + 3 * b2) - vec(d->xpos + 3 * b1));
            const Mat3 turn = r1.transpose() * r2;
            if ((at - vec(data + 3)).norm() > 1e-9 || (turn - quat(data + 6)).norm() > 1e-9)
                throw InputError(tree.file, "MJCF weld '" + name + "': its relpose is not the bodies' relative pose at "
                                            "qpos0; mbd welds them as they are at the start (leave relpose out, or "
                                            "place the bodies so that the weld holds at qpos0)");
        }
        tree.loops.push_back(loop);
    }
    return left;
}

// A geom as a shape of its body, posed in world at qpos0 (MuJoCo's geom_xpos, geom_xmat). MuJoCo keeps
// no mesh file names in the compiled model, and an ellipsoid has no mbd shape: those are not drawn.
bool geom_shape(const mjModel* m, const mjData* d, int g, VisualShape& shape) {
    const mjtNum* size = m->geom_size + 3 * g;
    switch (m->geom_type[g]) {
        case mjGEOM_SPHERE: shape.kind = ShapeKind::Sphere; shape.radius = size[0]; break;
        case mjGEOM_CAPSULE: shape.kind = ShapeKind::Capsule; shape.radius = size[0]; shape.length = 2 * size[1]; break;
        case mjGEOM_CYLINDER: shape.kind = ShapeKind::Cylinder; shape.radius = size[0]; shape.length = 2 * size[1]; break;
        case mjGEOM_BOX: shape.kind = ShapeKind::Box; shape.size = 2 * vec(size); break;
        default: return false;
    }
    shape.position = vec(d->geom_xpos + 3 * g);
    shape.rotation = mat(d->geom_xmat + 9 * g);
    const float* rgba = m->geom_rgba + 4 * g;
    shape.color = Vec3(rgba[0], rgba[1], rgba[2]);
    return true;
}

// MuJoCo's keyframes as named initial states: key_qpos against qpos0, key_qvel as it is.
void read_keyframes(const mjModel* m, SourceTree& tree) {
    for (int k = 0; k < m->nkey; ++k) {
        SourceKeyframe key;
        key.name = name_of(m, mjOBJ_KEY, k, "key");
        const mjtNum* qpos = m->key_qpos + k * m->nq;
        const mjtNum* qvel = m->key_qvel + k * m->nv;
        for (int j = 0; j < m->njnt; ++j) {
            const std::string joint = name_of(m, mjOBJ_JOINT, j, "joint");
            const int q = m->jnt_qposadr[j], v = m->jnt_dofadr[j], type = m->jnt_type[j];
            const int nq = type == mjJNT_FREE ? 7 : type == mjJNT_BALL ? 4 : 1, nv = type == mjJNT_FREE ? 6 : type == mjJNT_BALL ? 3 : 1;
            bool moved = false, moving = false;
            for (int i = 0; i < nq; ++i) moved |= qpos[q + i] != m->qpos0[q + i];
            for (int i = 0; i < nv; ++i) moving |= qvel[v + i] != 0.0;
            if (moving) key.velocities[joint] = std::vector<double>(qvel + v, qvel + v + nv);
            if (!moved) continue;
            if (type == mjJNT_FREE)
                key.free_poses[joint] = {vec(qpos + q), Vec4(qpos[q + 3], qpos[q + 4], qpos[q + 5], qpos[q + 6]).normalized()};
            else if (type == mjJNT_BALL)
                key.moved_balls.push_back(joint);
            else
                key.positions[joint] = qpos[q] - m->qpos0[q];
        }
        tree.keyframes.push_back(std::move(key));
    }
}

// The named elements of one kind (count n, names of type `type`).
std::vector<std::string> names(const mjModel* m, int type, int n, const char* kind) {
    std::vector<std::string> out;
    for (int k = 0; k < n; ++k) out.push_back(name_of(m, type, k, kind));
    return out;
}

void list_unmapped(const mjModel* m, SourceTree& tree) {
    auto add = [&](const std::string& kind, std::vector<std::string> list, const std::string& note) {
        if (!list.empty()) tree.unmapped.push_back({kind, std::move(list), note});
    };
    add("geoms", names(m, mjOBJ_GEOM, m->ngeom, "geom"), "contacts are not imported; spheres, capsules, cylinders and boxes are drawn, meshes and the rest not");
    add("sites", names(m, mjOBJ_SITE, m->nsite, "site"), "");
    add("tendons", names(m, mjOBJ_TENDON, m->ntendon, "tendon"), "");
    add("actuators", names(m, mjOBJ_ACTUATOR, m->nu, "actuator"), "");
    add("sensors", names(m, mjOBJ_SENSOR, m->nsensor, "sensor"), "");
    std::vector<std::string> limited, armature, friction, ball_damping;
    for (int j = 0; j < m->njnt; ++j) {
        const std::string name = name_of(m, mjOBJ_JOINT, j, "joint");
        const int dofs = m->jnt_type[j] == mjJNT_FREE ? 6 : m->jnt_type[j] == mjJNT_BALL ? 3 : 1;
        const int d0 = m->jnt_dofadr[j];
        bool has_armature = false, has_friction = false, has_damping = false;
        for (int k = d0; k < d0 + dofs; ++k) {
            has_armature |= m->dof_armature[k] != 0.0;
            has_friction |= m->dof_frictionloss[k] != 0.0;
            has_damping |= m->dof_damping[k] != 0.0;
        }
        if (m->jnt_limited[j] && dofs > 1) limited.push_back(name);  // a hinge's or slide's is a joint_stop
        if (has_armature && dofs > 1) armature.push_back(name);  // a hinge's or slide's is a rotor (scene_builder)
        if (has_friction) friction.push_back(name);
        if (dofs > 1 && (has_damping || m->jnt_stiffness[j] != 0.0)) ball_damping.push_back(name);
    }
    add("ball joint limits", limited, "a cone limit has no joint_stop");
    add("ball / free joint armatures", armature, "only a hinge's or slide's armature becomes a rotor; left out");
    add("joint friction losses", friction, "");
    add("ball / free joint springs and damping", ball_damping, "");
}


// The tree of the compiled model; the geoms of `placeholders` (drawn from missing meshes) are not drawn.
SourceTree read_tree(const mjModel* m, const std::string& file, const std::vector<int>& placeholders) {
    std::unique_ptr<mjData, void (*)(mjData*)> data(mj_makeData(m), mj_deleteData);
    mjData* d = data.get();
    for (int k = 0; k < m->nq; ++k) d->qpos[k] = m->qpos0[k];
    mj_kinematics(m, d);

    SourceTree tree;
    tree.file = file;
    tree.format = "MJCF";
    const char* model_name = m->names;  // the model's name is the first entry of names
    tree.name = (model_name && *model_name) ? model_name : std::filesystem::path(file).stem().string();
    tree.gravity = vec(m->opt.gravity);
    for (int b = 1; b < m->nbody; ++b) {  // body 0 is the world
        SourceBody body;
        body.name = name_of(m, mjOBJ_BODY, b, "body");
        body.where = file;
        body.parent = m->body_parentid[b] - 1;  // -1: the world
        body.mass = m->body_mass[b];
        const Mat3 principal = quat(m->body_iquat + 4 * b);  // inertial frame in the body frame
        body.inertia = principal * vec(m->body_inertia + 3 * b).asDiagonal() * principal.transpose();
        body.origin = vec(d->xpos + 3 * b);
        body.rotation = mat(d->xmat + 9 * b);
        body.com = vec(d->xipos + 3 * b);
        for (int j = m->body_jntadr[b]; j < m->body_jntadr[b] + m->body_jntnum[b]; ++j)
            body.joints.push_back(joint(m, d, j, file));
        tree.bodies.push_back(std::move(body));
    }
    for (int g = 0; g < m->ngeom; ++g) {  // the world's geoms (a floor) belong to no body
        VisualShape shape;
        shape.where = file + ": geom '" + name_of(m, mjOBJ_GEOM, g, "geom") + "'";
        const bool placeholder = std::find(placeholders.begin(), placeholders.end(), g) != placeholders.end();
        if (m->geom_bodyid[g] > 0 && !placeholder && geom_shape(m, d, g, shape)) tree.bodies[m->geom_bodyid[g] - 1].visuals.push_back(shape);
    }
    list_unmapped(m, tree);
    read_keyframes(m, tree);
    const std::vector<std::string> equalities = read_equalities(m, d, tree);
    if (!equalities.empty())
        tree.unmapped.push_back({"equality constraints", equalities,
                                 "tendon couplings and a joint equality without joint2 are not imported yet; inactive ones are left out"});
    return tree;
}

}  // namespace

SourceTree read_mjcf_model(const mjModel* m, const std::string& file) { return read_tree(m, file, {}); }

SourceTree read_mjcf_model(const MjcfCompilation& compiled, const std::string& file) {
    SourceTree tree = read_tree(compiled.model.get(), file, compiled.placeholder_geoms);
    std::vector<std::string> others;
    std::vector<std::string> missing = describe_missing(compiled, others);
    if (!others.empty())
        tree.unmapped.insert(tree.unmapped.begin(), {"more geoms from missing meshes", std::move(others),
                                                     "a mesh reading a file listed above, or a shape fitted to one; not drawn"});
    if (!missing.empty())
        tree.unmapped.insert(tree.unmapped.begin(),
                             {"missing mesh and texture files", std::move(missing),
                              "MuJoCo compiled the file with placeholders in their place, which are not drawn; no body's mass, "
                              "mass centre or inertia depends on them (compiled with two placeholder sizes, docs/import.md)"});
    return tree;
}

SourceTree read_mjcf(const std::filesystem::path& file) {
    const MjcfCompilation compiled = compile_mjcf(file);
    if (!compiled.model)
        throw InputError(file.string(), (compiled.inertia_from_missing_mesh ? "" : "MuJoCo's compiler refused the MJCF file: ") + compiled.error);
    return read_mjcf_model(compiled, file.string());
}

}  // namespace mbd::import
