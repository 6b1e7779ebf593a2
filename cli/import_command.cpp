// mbd import MODEL -o scene.yaml: an MJCF, URDF or SDF file as the equivalent mbd scene
// (docs/import.md), written only after it loads as a scene; what the import leaves out is
// listed in one warning (an error, exit 2, with --strict).
#include "commands.hpp"
#include "options.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>
#include <mbd/output_file.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/number.hpp>

#include <algorithm>
#include <iostream>

namespace mbd::cli {

namespace {

struct ImportArguments {
    std::string scene;  // the model file
    std::string output;
    bool strict = false;
    std::vector<std::string> velocities;  // NAME=V[,V...]
    std::vector<std::string> positions;   // NAME=V
    std::string keyframe;                 // an MJCF <key> by name
};

// "NAME=V[,V...]" given to `option` -> (NAME, the numbers)
std::pair<std::string, std::vector<double>> joint_values(const std::string& option, const std::string& given) {
    const size_t eq = given.find('=');
    if (eq == std::string::npos || eq == 0)
        throw InputError(option, "expected JOINT=VALUE[,VALUE...], got '" + given + "'");
    std::vector<double> values;
    const std::string rest = given.substr(eq + 1);
    for (size_t at = 0; at <= rest.size();) {
        const size_t comma = std::min(rest.find(',', at), rest.size());
        const std::string text = rest.substr(at, comma - at);
        double x = 0.0;
        if (parse_number(text, x) != NumberText::Valid)
            throw InputError(option, "'" + text + "' in '" + given + "' is not a finite number");
        values.push_back(x);
        at = comma + 1;
    }
    return {given.substr(0, eq), values};
}

// --velocity NAME=V[,V...] -> options.joint_velocities, --position NAME=V -> options.joint_positions
import::ImportOptions import_options(const ImportArguments& a) {
    import::ImportOptions options;
    options.keyframe = a.keyframe;
    for (const std::string& given : a.velocities) {
        auto [name, values] = joint_values("--velocity", given);
        options.joint_velocities[name] = values;
    }
    for (const std::string& given : a.positions) {
        const auto [name, values] = joint_values("--position", given);
        if (values.size() != 1)
            throw InputError("--position", "expected JOINT=VALUE (one number: a hinge's angle, a slide's travel), got '" + given + "'");
        options.joint_positions[name] = values[0];
    }
    return options;
}

}  // namespace

void add_import_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<ImportArguments>(
        app, "import",
        "Write the mbd scene of an MJCF (MuJoCo's compiler), URDF (urdfdom) or SDF (libsdformat) model file; list what it leaves out",
        "Model file: MJCF (<mujoco>), URDF (<robot>) or SDF (<sdf>), known from its content");
    sub->add_option("-o,--output", args->output, "The scene file to write (YAML)")->required();
    sub->add_flag("--strict", args->strict, "Refuse the model (exit 2, nothing written) when anything is left out");
    sub->add_option("--position", args->positions,
                    "Initial position of a hinge, slide or screw joint, JOINT=VALUE: its angle (rad) or travel (m) "
                    "from the model's reference configuration (MuJoCo's qpos - qpos0)");
    sub->add_option("--velocity", args->velocities,
                    "Initial velocity of a joint, JOINT=VALUE[,VALUE...] in MuJoCo's qvel convention (hinge, slide: "
                    "1 number; ball: 3, body axes; free: 6, origin velocity in world axes then angular velocity in "
                    "body axes); repeatable");
    sub->add_option("--keyframe", args->keyframe,
                    "Start from the MJCF keyframe (<key name=...>) of this name: its qpos and qvel; --position and "
                    "--velocity given beside it take precedence");
    commands[sub] = [args = args] {
        check_output_path(args->output, {args->scene}, "--output");
        const import::ImportedScene scene = import::import_model(args->scene, import_options(*args));
        const std::string missing = import::unmapped_summary(scene.unmapped);
        if (!missing.empty() && args->strict)
            throw InputError(args->scene, "--strict: the import would leave out " + missing);
        const std::string yaml = import::scene_yaml(scene);
        Registry registry;
        load_scene_text(yaml, args->output, registry);  // the scene must load before it is written
        OutputFile file(args->output);
        file.write_document_part(yaml);
        file.commit();
        if (!missing.empty()) std::cerr << "mbd: warning: " << args->scene << ": not imported: " << missing << "\n";
        std::cout << "imported " << args->scene << " (" << scene.format << "): " << scene.bodies.size() << " bodies, "
                  << scene.joints.size() << " joints, " << scene.forces.size() + scene.stops.size() << " forces -> " << args->output << "\n";
        return 0;
    };
}

}  // namespace mbd::cli
