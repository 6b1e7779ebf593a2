// mbd modes SCENE [--about statics|initial] [--json] [--output modes.csv]
// [--state-space AB.csv]: the equations of motion linearised in independent coordinates
// about a static equilibrium (the statics plugin's) or the scene's initial state taken as a
// steady motion; eigenvalues, natural frequencies, damping ratios and mode shapes, and the
// state-space matrices A and B. See docs/user-guide.md, "Modes".
#include "commands.hpp"
#include "options.hpp"

#include <mbd/app/modes_json.hpp>
#include <mbd/modes_study.hpp>
#include <mbd/output_file.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

namespace mbd::cli {

namespace {

struct ModesArguments {
    std::string scene;
    std::string about = "statics";
    bool json = false;
    std::string output;       // the mode table (CSV)
    std::string state_space;  // [A B] (CSV)
    double residual_tolerance = 1e-8;
    std::string solver = "ipopt";
    int statics_iterations = 500;
};

std::string number(double x) { return format_number(x, 17); }

// Numbers only: mode, oscillatory (1: a complex pair, shown by its Im > 0 member),
// ignorable (1: a cyclic coordinate, one the equations of motion do not depend on, its zero
// eigenvalue; never a mode whose eigenvalue is only small), eigenvalue,
// frequencies, damping, then the shape (re, im) in the independent coordinates and in the
// joint coordinates; the ignorable coordinates last.
std::string mode_table(const LinearModel& linear, const ModeAnalysis& analysis) {
    std::ostringstream s;
    s << "mode,oscillatory,ignorable,eigenvalue_real,eigenvalue_imag,natural_frequency_rad_s,natural_frequency_hz,damping_ratio";
    for (const std::string& c : linear.coordinates) s << ',' << c << "_re," << c << "_im";
    for (const std::string& j : linear.joint_coordinates) s << ",joint." << j << "_re,joint." << j << "_im";
    s << '\n';
    int index = 1;
    for (const Mode& m : analysis.modes) {
        s << index++ << ',' << (m.oscillatory ? 1 : 0) << ",0," << number(m.eigenvalue.real()) << ',' << number(m.eigenvalue.imag())
          << ',' << number(m.natural_frequency) << ',' << number(m.natural_frequency / (2 * M_PI)) << ','
          << number(m.damping_ratio);
        for (Eigen::Index c = 0; c < m.shape.size(); ++c) s << ',' << number(m.shape[c].real()) << ',' << number(m.shape[c].imag());
        for (Eigen::Index j = 0; j < m.joint_shape.size(); ++j)
            s << ',' << number(m.joint_shape[j].real()) << ',' << number(m.joint_shape[j].imag());
        s << '\n';
    }
    for (const IgnorableDirection& d : analysis.ignorable) {
        s << index++ << ",0,1,0,0,0,0,0";
        for (Eigen::Index c = 0; c < d.shape.size(); ++c) s << ',' << number(d.shape[c]) << ",0";
        for (Eigen::Index j = 0; j < d.joint_shape.size(); ++j) s << ',' << number(d.joint_shape[j]) << ",0";
        s << '\n';
    }
    return s.str();
}

// One row per state, in the order of the A columns: its row of A, then its row of B.
std::string state_space_table(const LinearModel& linear) {
    const std::vector<std::string> names = state_names(linear);
    std::ostringstream s;
    const char* separator = "";
    for (const std::string& n : names) s << separator << "A." << n, separator = ",";
    for (const std::string& n : linear.inputs) s << separator << "B." << n, separator = ",";
    s << '\n';
    for (Eigen::Index i = 0; i < linear.A.rows(); ++i) {
        for (Eigen::Index j = 0; j < linear.A.cols(); ++j) s << (j ? "," : "") << number(linear.A(i, j));
        for (Eigen::Index j = 0; j < linear.B.cols(); ++j) s << ',' << number(linear.B(i, j));
        s << '\n';
    }
    return s.str();
}

void print_report(const std::string& scene, const std::string& about, const LinearModel& linear,
                  const ModeAnalysis& analysis) {
    std::printf("modes of %s about %s (residual max |vdot_i| = %.3e)\n", scene.c_str(),
                about == "statics" ? "the static equilibrium" : "the initial state", linear.residual);
    std::printf("independent coordinates:");
    for (const std::string& c : linear.coordinates) std::printf(" %s", c.c_str());
    if (linear.velocity_coordinates != linear.coordinates) {
        std::printf("\nindependent velocities:");
        for (const std::string& c : linear.velocity_coordinates) std::printf(" %s", c.c_str());
    }
    std::printf("\n\n  mode  %-13s %26s %16s %14s %12s\n", "kind", "eigenvalue (1/s)", "omega_n (rad/s)", "f_n (Hz)",
                "damping");
    int index = 1;
    for (const Mode& m : analysis.modes)
        std::printf("  %4d  %-13s %12.8g %+12.8gi %16.10g %14.8g %12.8g\n", index++, mode_kind(m), m.eigenvalue.real(),
                    m.eigenvalue.imag(), m.natural_frequency, m.natural_frequency / (2 * M_PI), m.damping_ratio);
    for (const IgnorableDirection& d : analysis.ignorable)
        std::printf("  %4d  %-13s %12.8g %+12.8gi   cyclic: the equations of motion do not depend on %s%s\n", index++,
                    "ignorable", 0.0, 0.0, d.single ? "" : "the combination ", describe(d, linear.coordinates).c_str());
}

void write_file(const std::string& path, const std::string& text) {
    OutputFile file(path);
    file.replace(text);
    file.commit();
}

}  // namespace

void add_modes_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<ModesArguments>(
        app, "modes", "Linearised equations of motion: eigenvalues, natural frequencies, damping ratios, mode "
                      "shapes, state-space A and B");
    sub->add_option("--about", args->about,
                    "statics (the static equilibrium found by the statics plugin) or initial (the scene's initial "
                    "state, taken as an equilibrium or steady motion)")
        ->capture_default_str()
        ->check(CLI::IsMember({"statics", "initial"}));
    sub->add_flag("--json", args->json, "Print one JSON object (modes, A, B) instead of the report");
    sub->add_option("-o,--output", args->output, "Write the modes as CSV");
    sub->add_option("--state-space", args->state_space, "Write A and B as CSV (one row per state)");
    sub->add_option("--residual-tolerance", args->residual_tolerance,
                    "Largest independent acceleration accepted at the reference state")
        ->capture_default_str()
        ->check(positive_number());
    sub->add_option("--solver", args->solver, "Statics plugin type (--about statics)")->capture_default_str();
    sub->add_option("--statics-iterations", args->statics_iterations, "Ipopt iterations of the statics (--about statics)")
        ->capture_default_str()
        ->check(positive_number());

    commands[sub] = [args = args] {
        Registry registry;
        const Model model = load_scene_file(args->scene, registry);
        check_output_path(args->output, scene_files(args->scene, model), "--output");
        check_output_path(args->state_space, scene_files(args->scene, model), "--state-space");
        ModesStudyOptions options;
        options.about = args->about;
        options.residual_tolerance = args->residual_tolerance;
        options.solver = args->solver;
        options.statics_iterations = args->statics_iterations;
        const ModesStudy study = study_modes(model, registry, options);
        if (!study.statics_converged) {
            std::cerr << "mbd: error: no modes: the statics of " << args->scene
                      << " did not converge: " << study.statics_message << '\n';
            return 1;
        }
        const LinearModel& linear = study.linear;
        const ModeAnalysis& analysis = study.analysis;
        if (args->json) std::cout << json_text(modes_json(args->about, linear, analysis)) << std::endl;
        else print_report(args->scene, args->about, linear, analysis);
        if (!args->output.empty()) write_file(args->output, mode_table(linear, analysis));
        if (!args->state_space.empty()) write_file(args->state_space, state_space_table(linear));
        return 0;
    };
}

}  // namespace mbd::cli
