// MuJoCo peer of the work-precision benchmark (bench/peers/peer_common.hpp): the benchmark
// models written in MJCF (generalized coordinates: hinge, slide and ball joints; loop closures
// are MuJoCo's soft `connect` equality constraints, made as stiff as the step allows;
// spring-dampers are spatial tendons; a driven joint gets, at every evaluation, the generalized
// force that gives it the prescribed acceleration) and integrated with MuJoCo's fixed-step
// integrators (rk4: RK4, euler: semi-implicit Euler) at the given step (shortened so that the
// output step is a whole number of steps). Contacts are disabled.
// A model file (MJCF or URDF) is compiled by MuJoCo itself, as it is but for contacts (off), the
// integrator and the step; URDF without its <visual> and <collision> elements (the dynamics uses
// the explicit <inertial> only, and MuJoCo refuses meshes it cannot find); an MJCF file's missing
// mesh files get placeholders as in the import (import/mjcf_compile.hpp). Its measured points
// are the named bodies' mass centres (xipos).
#include "peer_common.hpp"

#include <mbd/import/mjcf_compile.hpp>
#include <mujoco/mujoco.h>

#include <array>
#include <ctime>
#include <fstream>
#include <functional>
#include <regex>
#include <stdexcept>
#include <sstream>
#include <unistd.h>

namespace {

// A model: MJCF fragments, the measured points and the initial state.
struct Model {
    std::string gravity;          // the option's gravity attribute
    std::string worldbody;        // the content of <worldbody>
    std::string after;            // elements after <worldbody> (equality, tendon)
    // included files: "<include file=\"@k\"/>" in the fragments stands for includes[k] (a
    // <mujocoinclude> document), written to a temporary file of its own
    std::vector<std::string> includes;
    std::vector<std::pair<std::string, std::array<double, 3>>> measured;  // body, point in its frame
    std::vector<std::pair<std::string, double>> qpos, qvel;              // scalar joints by name
    std::function<void(const mjModel*, mjData*)> init;                   // any other initial state
    // rheonomic driver: the joint whose acceleration is prescribed as a function of time
    std::string driven_joint;
    std::function<double(double)> driven_acceleration;
};

std::string vec(double x, double y, double z) {
    char b[100];
    std::snprintf(b, sizeof b, "%.17g %.17g %.17g", x, y, z);
    return b;
}

// The loop-closure settings of a connect constraint: time constant of twice the step (the
// stiffest MuJoCo integrates stably), critical damping, the maximal impedance 0.9999.
std::string stiff_connect(double h) {
    char b[100];
    std::snprintf(b, sizeof b, " solref=\"%.17g 1\" solimp=\"0.9999 0.9999 0.001\"", 2 * h);
    return b;
}

// IFToMM A01: point mass 1 kg (tiny inertia 1e-6 as in the scene) 1 m from the pivot.
Model build_pendulum() {
    Model m;
    m.gravity = "0 -9.81 0";
    m.worldbody = "<body name=\"bob\"><joint type=\"hinge\" axis=\"0 0 1\"/>"
                  "<inertial pos=\"1 0 0\" mass=\"1\" diaginertia=\"1e-6 1e-6 1e-6\"/></body>";
    m.measured = {{"bob", {1, 0, 0}}};
    return m;
}

// IFToMM A02 with n loops: n+1 cranks pinned to the ground at x = 0..n (frames turned to point
// up), coupler k hinged to the tip of crank k and connected to the tip of crank k+1. Rods of
// 1 m, 1 kg along body x, frame at one end. Start: crank rate -1 (tip B0 at 1 m/s along +x),
// couplers translating (relative rate +1). Measured: the tip of crank 0.
Model build_four_bar(int n, double h) {
    Model m;
    m.gravity = "0 -9.81 0";
    const std::string rod = "<inertial pos=\"0.5 0 0\" mass=\"1\" diaginertia=\"1e-6 0.0833333333333333 0.0833333333333333\"/>";
    std::ostringstream x, eq;
    for (int i = 0; i <= n; ++i) {
        x << "<body name=\"crank" << i << "\" pos=\"" << i << " 0 0\" euler=\"0 0 90\">"
          << "<joint name=\"crank" << i << "\" type=\"hinge\" axis=\"0 0 1\"/>" << rod;
        m.qvel.push_back({"crank" + std::to_string(i), -1.0});
        if (i < n) {
            x << "<body name=\"coupler" << i << "\" pos=\"1 0 0\" euler=\"0 0 -90\">"
              << "<joint name=\"coupler" << i << "\" type=\"hinge\" axis=\"0 0 1\"/>" << rod << "</body>";
            m.qvel.push_back({"coupler" + std::to_string(i), 1.0});
            eq << "<connect body1=\"coupler" << i << "\" body2=\"crank" << i + 1 << "\" anchor=\"1 0 0\""
               << stiff_connect(h) << "/>";
        }
        x << "</body>";
    }
    m.worldbody = x.str();
    m.after = "<equality>" + eq.str() + "</equality>";
    m.measured = {{"crank0", {1, 0, 0}}};
    return m;
}

// Planar chain of n links (0.1 m, 1 kg, I = m L^2 / 12), released at rest horizontally. The
// MJCF parser (tinyxml2) refuses elements nested deeper than about 100 levels, so the nested
// bodies are split into included files of 80 links each (each file is parsed on its own; the
// include is replaced by its content before the model is compiled).
Model build_chain(int n) {
    Model m;
    m.gravity = "0 -9.81 0";
    const int per_file = 80;
    std::vector<std::ostringstream> files((n + per_file - 1) / per_file);
    for (int k = 0; k < n; ++k)
        files[k / per_file] << "<body name=\"l" << k << "\" pos=\"" << (k == 0 ? 0.0 : 0.1) << " 0 0\">"
                            << "<joint type=\"hinge\" axis=\"0 0 1\"/>"
                            << "<inertial pos=\"0.05 0 0\" mass=\"1\" diaginertia=\"1e-9 0.000833333333333333 0.000833333333333333\"/>";
    for (size_t f = 0; f < files.size(); ++f) {
        if (f + 1 < files.size()) files[f] << "<include file=\"@" << f << "\"/>";
        const int links = std::min(n, static_cast<int>(f + 1) * per_file) - static_cast<int>(f) * per_file;
        for (int k = 0; k < links; ++k) files[f] << "</body>";
    }
    m.worldbody = files[0].str();
    for (size_t f = 1; f < files.size(); ++f) m.includes.push_back("<mujocoinclude>" + files[f].str() + "</mujocoinclude>");
    for (int k : chain_measured(n)) m.measured.push_back({"l" + std::to_string(k), {0.1, 0, 0}});
    return m;
}

// Heavy symmetric top on a ball joint at the world origin (body frame at the pivot, the mass
// centre l up the body z axis), tilted pi/6 about x; MuJoCo's ball-joint velocity is the angular
// velocity in the body frame, so the scene's world-frame omega is rotated back by R^T.
Model build_gyroscope() {
    using namespace gyroscope;
    Model m;
    m.gravity = vec(0, 0, -g);
    m.worldbody = "<body name=\"top\"><joint name=\"ball\" type=\"ball\"/><inertial pos=\"" + vec(0, 0, l) +
                  "\" mass=\"" + std::to_string(mass) + "\" diaginertia=\"" + vec(ixx, ixx, izz) + "\"/></body>";
    m.init = [](const mjModel* model, mjData* d) {
        const int j = mj_name2id(model, mjOBJ_JOINT, "ball");
        mjtNum* q = d->qpos + model->jnt_qposadr[j];
        q[0] = std::cos(tilt / 2);
        q[1] = std::sin(tilt / 2);
        q[2] = q[3] = 0;
        const double c = std::cos(tilt), s = std::sin(tilt);  // R = Rx(tilt); R^T omega
        mjtNum* w = d->qvel + model->jnt_dofadr[j];
        w[0] = omega[0];
        w[1] = c * omega[1] + s * omega[2];
        w[2] = -s * omega[1] + c * omega[2];
    };
    m.measured = {{"top", {0, 0, l}}};
    return m;
}

// IFToMM A04 Bricard linkage: a hinge tree world-bar1-...-bar5 (body frames at the bar
// centres, parallel to the world); the sixth revolute joint (bar5-world at (0, 0, 1), axis x)
// closes the loop as two connect constraints at two points of its axis (6 rows for its 5; the
// mechanism adds one more redundant row; MuJoCo's regularized solver takes both).
Model build_bricard(double h) {
    using namespace bricard;
    Model m;
    m.gravity = vec(0, -g, 0);
    std::ostringstream x;
    double parent[3] = {0, 0, 0};
    for (int k = 0; k < 5; ++k) {
        const double* c = centre[k];
        double inertia[3] = {transverse, transverse, transverse};
        inertia[bar_axis[k]] = axial;
        double axis[3] = {0, 0, 0};
        axis[joint_axis[k]] = 1;
        const double* p = joint_point[k];
        x << "<body name=\"bar" << k + 1 << "\" pos=\"" << vec(c[0] - parent[0], c[1] - parent[1], c[2] - parent[2])
          << "\"><joint type=\"hinge\" pos=\"" << vec(p[0] - c[0], p[1] - c[1], p[2] - c[2]) << "\" axis=\""
          << vec(axis[0], axis[1], axis[2]) << "\"/><inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\""
          << vec(inertia[0], inertia[1], inertia[2]) << "\"/>";
        for (int i = 0; i < 3; ++i) parent[i] = c[i];
    }
    for (int k = 0; k < 5; ++k) x << "</body>";
    m.worldbody = x.str();
    const double* p = joint_point[5];
    double e[3] = {0, 0, 0};
    e[joint_axis[5]] = 1;
    const double* c5 = centre[4];
    m.after = "<equality><connect body1=\"bar5\" anchor=\"" + vec(p[0] - c5[0], p[1] - c5[1], p[2] - c5[2]) + "\"" +
              stiff_connect(h) + "/><connect body1=\"bar5\" anchor=\"" +
              vec(p[0] + e[0] - c5[0], p[1] + e[1] - c5[1], p[2] + e[2] - c5[2]) + "\"" + stiff_connect(h) +
              "/></equality>";
    const double* c3 = centre[2];
    const double* p3 = joint_point[3];
    m.measured = {{"bar3", {p3[0] - c3[0], p3[1] - c3[1], p3[2] - c3[2]}}};
    return m;
}

// IFToMM A05 flyball governor: shaft hinge about z driven at a constant rate (prescribed zero
// acceleration from the initial rate), two arms hinged to the shaft top about y, the slider on a
// slide joint along the shaft; each spring-damper is a spatial tendon (stiffness, damping,
// spring length) between the rod midpoint and the slider centre. Body frames at the mass centres.
Model build_flyball() {
    using namespace flyball;
    Model m;
    m.gravity = vec(0, 0, -g);
    std::ostringstream x, t;
    x << "<body name=\"shaft\" pos=\"" << vec(0, 0, shaft_com_z) << "\"><joint name=\"spin\" type=\"hinge\" pos=\""
      << vec(0, 0, -shaft_com_z) << "\" axis=\"0 0 1\"/><inertial pos=\"0 0 0\" mass=\"" << shaft_mass
      << "\" diaginertia=\"" << vec(shaft_inertia[0], shaft_inertia[1], shaft_inertia[2]) << "\"/>";
    const char* names[2] = {"armL", "armR"};
    for (int k = 0; k < 2; ++k) {
        const double side = k == 0 ? 1.0 : -1.0;
        const double c[3] = {side * arm_com[0], arm_com[1], arm_com[2]};
        char inertia[200];
        std::snprintf(inertia, sizeof inertia, "%.17g %.17g %.17g %.17g %.17g %.17g", arm_inertia[0], arm_inertia[1],
                      arm_inertia[2], arm_inertia[3], side * arm_inertia[4], arm_inertia[5]);
        x << "<body name=\"" << names[k] << "\" pos=\"" << vec(c[0], c[1], c[2] - shaft_com_z)
          << "\"><joint type=\"hinge\" pos=\"" << vec(-c[0], -c[1], pivot_z - c[2]) << "\" axis=\"0 1 0\"/>"
          << "<inertial pos=\"0 0 0\" mass=\"" << arm_mass << "\" fullinertia=\"" << inertia << "\"/>"
          << "<site name=\"mid" << k << "\" pos=\""
          << vec(side * arm_spring_point[0], arm_spring_point[1], arm_spring_point[2]) << "\"/></body>";
        t << "<spatial stiffness=\"" << stiffness << "\" damping=\"" << damping << "\" springlength=\"" << rest_length
          << "\"><site site=\"mid" << k << "\"/><site site=\"slider\"/></spatial>";
    }
    x << "<body name=\"slider\" pos=\"" << vec(0, 0, slider_z - shaft_com_z)
      << "\"><joint type=\"slide\" axis=\"0 0 1\"/><inertial pos=\"0 0 0\" mass=\"" << slider_mass
      << "\" diaginertia=\"" << vec(slider_inertia, slider_inertia, slider_inertia)
      << "\"/><site name=\"slider\"/></body></body>";
    m.worldbody = x.str();
    m.after = "<tendon>" + t.str() + "</tendon>";
    m.qvel = {{"spin", spin_rate}};
    m.driven_joint = "spin";
    m.driven_acceleration = [](double) { return 0.0; };
    m.measured = {{"slider", {0, 0, 0}}};
    return m;
}

// Test Set car axis as a tree: the bump body turns about the origin with the prescribed angle
// phi(t) (driven joint; its point (1, 0) is b(t)); the left wheel slides along the bump's y axis
// (the scene's prismatic joint); the right wheel hangs from the left one on a massless rod of
// length 1 (the scene's distance joint). The wheels are point masses (the scene's 1e-9 inertia
// rides on the prescribed bump rotation or on a free rotation no force acts on; MuJoCo needs a
// positive value, 1e-15 here). Springs (k = 1, rest 0.5) are tendons origin-left and
// b(t)-right; g = 1 along -y.
Model build_car_axis() {
    Model m;
    m.gravity = "0 -1 0";
    const std::string wheel = "mass=\"0.0005\" diaginertia=\"1e-15 1e-15 1e-15\"/>";
    m.worldbody = "<site name=\"origin\"/>"
                  "<body name=\"bump\"><joint name=\"bump\" type=\"hinge\" axis=\"0 0 1\"/>"
                  "<inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 1\"/><site name=\"b\" pos=\"1 0 0\"/>"
                  "<body name=\"left\"><joint name=\"left\" type=\"slide\" axis=\"0 1 0\"/><inertial pos=\"0 0 0\" " +
                  wheel +
                  "<site name=\"left\"/>"
                  "<body name=\"right\"><joint name=\"right\" type=\"hinge\" axis=\"0 0 1\"/><inertial pos=\"1 0 0\" " +
                  wheel + "<site name=\"right\" pos=\"1 0 0\"/></body></body></body>";
    m.after = "<tendon><spatial stiffness=\"1\" springlength=\"0.5\"><site site=\"origin\"/><site site=\"left\"/></spatial>"
              "<spatial stiffness=\"1\" springlength=\"0.5\"><site site=\"b\"/><site site=\"right\"/></spatial></tendon>";
    m.qpos = {{"left", 0.5}};
    const double phid0 = car_axis_bump_angle(0).phid;
    m.qvel = {{"bump", phid0}, {"right", -phid0}};  // the rod at rest in the world, the left frame turns
    m.driven_joint = "bump";
    m.driven_acceleration = [](double t) { return car_axis_bump_angle(t).phidd; };
    m.measured = {{"left", {0, 0, 0}}, {"right", {1, 0, 0}}};
    return m;
}

// The driven joint: a generalized force on its dof that gives it the prescribed acceleration
// a(t): without it, qacc = M^-1 f (f = passive - bias, no other applied or constraint force in
// the driven models); adding tau e_d gives qacc_d = (M^-1 f)_d + tau (M^-1)_dd. This is the
// Lagrange multiplier of the rheonomic constraint, computed exactly at every evaluation (MuJoCo
// calls the control callback after the velocity stage of each RK4 stage).
struct Driver {
    int dof = -1;
    std::function<double(double)> acceleration;
};
Driver g_driver;

void apply_driver(const mjModel* m, mjData* d) {
    if (g_driver.dof < 0) return;
    std::vector<mjtNum> f(m->nv), a(m->nv), e(m->nv, 0.0), col(m->nv);
    for (int i = 0; i < m->nv; ++i) f[i] = d->qfrc_passive[i] - d->qfrc_bias[i];
    mj_solveM(m, d, a.data(), f.data(), 1);
    e[g_driver.dof] = 1.0;
    mj_solveM(m, d, col.data(), e.data(), 1);
    d->qfrc_applied[g_driver.dof] = (g_driver.acceleration(d->time) - a[g_driver.dof]) / col[g_driver.dof];
}

// Write text to a new temporary file /tmp/mbd_peer_mujoco_XXXXXX.xml; returns its path ("" on failure).
std::string write_temporary(const std::string& text) {
    char path[] = "/tmp/mbd_peer_mujoco_XXXXXX.xml";
    const int fd = ::mkstemps(path, 4);
    if (fd < 0) return "";
    const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
    ::close(fd);
    if (!written) ::unlink(path);
    return written ? path : "";
}

mjModel* compile(const Model& model, double h, const std::string& integrator) {
    // the included files, last first, so that each one's own include names an existing file
    std::vector<std::string> paths(model.includes.size());
    const auto substitute = [&paths](std::string text) {
        for (size_t k = 0; k < paths.size(); ++k) {
            const std::string key = "\"@" + std::to_string(k) + "\"";
            const std::string name = "\"" + paths[k].substr(paths[k].rfind('/') + 1) + "\"";  // relative to the model
            for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at)) text.replace(at, key.size(), name);
        }
        return text;
    };
    for (size_t k = paths.size(); k-- > 0;) paths[k] = write_temporary(substitute(model.includes[k]));
    std::ostringstream x;
    char opt[300];
    std::snprintf(opt, sizeof opt,
                  "<option timestep=\"%.17g\" integrator=\"%s\" gravity=\"%s\" tolerance=\"1e-14\" iterations=\"200\">",
                  h, integrator.c_str(), model.gravity.c_str());
    x << "<mujoco>" << opt << "<flag contact=\"disable\" refsafe=\"disable\"/></option><worldbody>" << model.worldbody
      << "</worldbody>" << model.after << "</mujoco>";
    const std::string path = write_temporary(substitute(x.str()));
    char error[1000] = "";
    mjModel* m = path.empty() ? nullptr : mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    if (!path.empty()) ::unlink(path.c_str());
    for (const auto& p : paths)
        if (!p.empty()) ::unlink(p.c_str());
    if (!m) std::fprintf(stderr, "mujoco peer: %s\n", error);
    return m;
}

// A model file compiled by MuJoCo (URDF through a geometry-free copy in /tmp; the file itself is
// never written), null with the compiler's message on stderr.
mjModel* compile_file(const std::string& file) {
    std::string path = file, copy;
    if (file.size() > 5 && file.substr(file.size() - 5) == ".urdf") {
        std::ifstream in(file);
        std::stringstream text;
        text << in.rdbuf();
        static const std::regex geometry("<visual[\\s>][\\s\\S]*?</visual>|<collision[\\s>][\\s\\S]*?</collision>");
        char name[] = "/tmp/mbd_peer_mujoco_XXXXXX.urdf";
        const int fd = ::mkstemps(name, 5);
        if (fd < 0) return nullptr;
        const std::string stripped = std::regex_replace(text.str(), geometry, "");
        const bool written = ::write(fd, stripped.data(), stripped.size()) == static_cast<ssize_t>(stripped.size());
        ::close(fd);
        path = copy = name;
        if (!written || !in) {
            ::unlink(name);
            std::fprintf(stderr, "mujoco peer: cannot read %s\n", file.c_str());
            return nullptr;
        }
    }
    // as the import compiles it: placeholders for missing meshes (import/mjcf_compile)
    mbd::import::MjcfCompilation compiled = mbd::import::compile_mjcf(path);
    if (!copy.empty()) ::unlink(copy.c_str());
    if (!compiled.model) std::fprintf(stderr, "mujoco peer: %s: %s\n", file.c_str(), compiled.error.c_str());
    return compiled.model.release();
}

// The model file's run: its measured mass centres (xipos) and initial velocities by name.
Model file_model(const PeerArgs& a, const mjModel* m) {
    Model model;
    for (const std::string& name : a.bodies) model.measured.push_back({name, {0, 0, 0}});
    model.init = [velocities = a.velocities](const mjModel* m, mjData* d) {
        for (const auto& [name, v] : velocities) {
            const int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
            for (size_t k = 0; k < v.size(); ++k) d->qvel[m->jnt_dofadr[j] + k] = v[k];
        }
    };
    for (const auto& [name, v] : a.velocities) {
        const int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
        const size_t dofs = j < 0 ? 0 : m->jnt_type[j] == mjJNT_FREE ? 6 : m->jnt_type[j] == mjJNT_BALL ? 3 : 1;
        if (dofs != v.size()) throw std::runtime_error("no joint '" + name + "' with " + std::to_string(v.size()) + " velocities");
    }
    return model;
}

void set_initial_state(const Model& model, const mjModel* m, mjData* d) {
    for (const auto& [name, q] : model.qpos) d->qpos[m->jnt_qposadr[mj_name2id(m, mjOBJ_JOINT, name.c_str())]] = q;
    for (const auto& [name, u] : model.qvel) d->qvel[m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, name.c_str())]] = u;
    if (model.init) model.init(m, d);
}

// The benchmark's named models; false for an unknown name.
bool named_model(const std::string& name, double h, Model& model) {
    if (name == "pendulum_a01") model = build_pendulum();
    else if (const int n = four_bar_loops(name)) model = build_four_bar(n, h);
    else if (const int n = chain_links(name)) model = build_chain(n);
    else if (name == "gyroscope") model = build_gyroscope();
    else if (name == "bricard") model = build_bricard(h);
    else if (name == "flyball") model = build_flyball();
    else if (name == "car_axis") model = build_car_axis();
    else return false;
    return true;
}

// A model file compiled by MuJoCo itself at the step h, contacts off; its measured bodies read
// into `model`. Null (the cause printed) when it cannot be read.
mjModel* compile_model_file(const PeerArgs& a, double h, Model& model) {
    mjModel* m = compile_file(a.model);
    if (!m) return nullptr;
    m->opt.timestep = h;
    m->opt.integrator = a.integrator == "euler" ? mjINT_EULER : mjINT_RK4;
    m->opt.disableflags |= mjDSBL_CONTACT;
    try {
        model = file_model(a, m);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mujoco peer: %s: %s\n", a.model.c_str(), e.what());
        mj_deleteModel(m);
        return nullptr;
    }
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    const PeerArgs a = parse_peer_args(argc, argv);
    // A MuJoCo warning (a diverging run, which MuJoCo would reset to the initial state and go
    // on) fails the run, on stderr, and writes no MUJOCO_LOG.TXT into the user's folder.
    mju_user_warning = [](const char* message) {
        std::fprintf(stderr, "mujoco peer: %s\n", message);
        std::exit(1);
    };
    if (a.tolerance) {
        std::fprintf(stderr, "mujoco peer: only fixed steps (step VALUE)\n");
        return 2;
    }
    const long per_output = std::max(1L, static_cast<long>(std::ceil(a.output_step / a.value - 1e-9)));
    const double h = a.output_step / per_output;
    Model model;
    mjModel* m = nullptr;
    if (is_model_file(a.model)) {
        m = compile_model_file(a, h, model);
        if (!m) return 2;
    } else if (!named_model(a.model, h, model)) {
        std::fprintf(stderr, "mujoco peer: unknown model '%s'\n", a.model.c_str());
        return 2;
    }
    if (!m) m = compile(model, h, a.integrator == "euler" ? "Euler" : "RK4");
    if (!m) return 1;
    mjData* d = mj_makeData(m);
    set_initial_state(model, m, d);
    if (!model.driven_joint.empty()) {
        g_driver.dof = m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, model.driven_joint.c_str())];
        g_driver.acceleration = model.driven_acceleration;
        mjcb_control = apply_driver;
    }
    std::vector<int> bodies;
    for (const auto& [name, p] : model.measured) {
        bodies.push_back(mj_name2id(m, mjOBJ_BODY, name.c_str()));
        if (bodies.back() < 0) {
            std::fprintf(stderr, "mujoco peer: no body '%s' in %s\n", name.c_str(), a.model.c_str());
            return 2;
        }
    }
    // named models: a point of the body frame; model files: the mass centre
    const mjtNum* positions = is_model_file(a.model) ? d->xipos : d->xpos;
    const std::vector<double> times = peer_output_times(a);
    std::vector<std::vector<double>> rows;
    long steps = 0;
    const std::clock_t start = std::clock();
    for (double t : times) {
        const long target = std::lround(t / h);
        while (steps < target) {
            mj_step(m, d);
            ++steps;
        }
        mj_kinematics(m, d);
        std::vector<double> row{t};
        for (size_t k = 0; k < bodies.size(); ++k) {
            const double* p = positions + 3 * bodies[k];
            const double* R = d->xmat + 9 * bodies[k];
            const auto& s = model.measured[k].second;
            for (int i = 0; i < 3; ++i) row.push_back(p[i] + R[3 * i] * s[0] + R[3 * i + 1] * s[1] + R[3 * i + 2] * s[2]);
        }
        rows.push_back(row);
    }
    const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    print_peer_result(cpu, steps, rows);
    mj_deleteData(d);
    mj_deleteModel(m);
    return 0;
}
