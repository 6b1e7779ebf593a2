// mbd import MODEL -o scene.yaml: an MJCF or URDF file as the equivalent mbd scene
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
};

// --velocity NAME=V[,V...] -> options.joint_velocities
import::ImportOptions import_options(const ImportArguments& a) {
    import::ImportOptions options;
    for (const std::string& given : a.velocities) {
        const size_t eq = given.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("--velocity", "expected JOINT=VALUE[,VALUE...], got '" + given + "'");
        std::vector<double>& values = options.joint_velocities[given.substr(0, eq)];
        std::string rest = given.substr(eq + 1);
        for (size_t at = 0; at <= rest.size();) {
            const size_t comma = std::min(rest.find(',', at), rest.size());
            const std::string text = rest.substr(at, comma - at);
            double x = 0.0;
            if (parse_number(text, x) != NumberText::Valid)
                throw InputError("--velocity", "'" + text + "' in '" + given + "' is not a finite number");
            values.push_back(x);
            at = comma + 1;
        }
    }
    return options;
}

}  // namespace

void add_import_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<ImportArguments>(
        app, "import",
        "Write the mbd scene of an MJCF (MuJoCo's compiler) or URDF (urdfdom) model file; list what it leaves out",
        "Model file: MJCF (<mujoco>) or URDF (<robot>), known from its content");
    sub->add_option("-o,--output", args->output, "The scene file to write (YAML)")->required();
    sub->add_flag("--strict", args->strict, "Refuse the model (exit 2, nothing written) when anything is left out");
    sub->add_option("--velocity", args->velocities,
                    "Initial velocity of a joint, JOINT=VALUE[,VALUE...] in MuJoCo's qvel convention (hinge, slide: "
                    "1 number; ball: 3, body axes; free: 6, origin velocity in world axes then angular velocity in "
                    "body axes); repeatable");
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
                  << scene.joints.size() << " joints, " << scene.forces.size() << " forces -> " << args->output << "\n";
        return 0;
    };
}

}  // namespace mbd::cli
