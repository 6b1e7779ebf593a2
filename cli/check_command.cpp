// mbd check SCENE: load and assemble a scene, and report its mobility.
#include "commands.hpp"
#include "options.hpp"

#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/scene_check.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <iostream>

namespace mbd::cli {

namespace {

std::string body_list(const Model& model, const std::vector<int>& bodies) {
    std::string out;
    for (size_t k = 0; k < bodies.size(); ++k) {
        if (k) out += ", ";
        out += model.body_name(bodies[k]);
    }
    return out;
}

std::string plural(int n, const char* word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

}  // namespace

void add_check_command(CLI::App& app, Commands& commands) {
    auto scene = std::make_shared<std::string>();
    auto tolerance = std::make_shared<double>(1e-9);
    CLI::App* sub = add_scene_subcommand(app, "check",
                                         "Load and assemble a scene; print its bodies, joints, forces, drivers, degrees "
                                         "of freedom (Gruebler count and rank of C_q) and redundant constraints",
                                         *scene);
    sub->add_option("--rank-tolerance", *tolerance, "Relative tolerance of the rank of C_q")
        ->capture_default_str()
        ->check(number_between(1e-16, 1.0));

    commands[sub] = [scene, tolerance] {
        Registry registry;
        const Model model = load_scene_file(*scene, registry);
        std::cout << "scene: " << *scene << " (" << to_string(model.dimension) << ")\n";

        size_t width = 4;
        for (const auto& b : model.bodies) width = std::max(width, b.name.size());
        for (const auto& j : model.joints) width = std::max(width, j.name.size());
        for (const auto& f : model.forces) width = std::max(width, f.name.size());
        for (const auto& d : model.drivers) width = std::max(width, d.name.size());
        const int w = static_cast<int>(width) + 2;
        size_t type_width = 13;  // a type column at least 14 wide, wider for a longer type (collision_contact)
        for (const auto& j : model.joints) type_width = std::max(type_width, j.type.size());
        for (const auto& f : model.forces) type_width = std::max(type_width, f.type.size());
        const int tw = static_cast<int>(type_width) + 1;

        std::cout << "\nbodies (" << model.bodies.size() << "):\n";
        for (const auto& b : model.bodies) std::cout << "  " << std::left << std::setw(w) << b.name << "mass " << format_number(b.mass) << '\n';
        std::cout << "joints (" << model.joints.size() << "):\n";
        for (const auto& j : model.joints)
            std::cout << "  " << std::left << std::setw(w) << j.name << std::setw(tw) << j.type << body_list(model, j.bodies)
                      << "  (" << plural(j.joint->rows(), "equation") << ")\n";
        std::cout << "forces (" << model.forces.size() << "):\n";
        for (const auto& f : model.forces)
            std::cout << "  " << std::left << std::setw(w) << f.name << std::setw(tw) << f.type << body_list(model, f.bodies) << '\n';
        std::cout << "drivers (" << model.drivers.size() << "):\n";
        for (const auto& d : model.drivers)
            std::cout << "  " << std::left << std::setw(w) << d.name << "drives joint '" << model.joints[d.joint].name
                      << "' (" << model.joints[d.joint].type << ")\n";

        const SceneCheck check = check_scene(model, *tolerance);
        std::cout << "\nassembled at t = 0 in " << plural(check.assembly.iterations, "Newton iteration") << " (max |C| = "
                  << format_number(check.assembly.residual) << ")\n";

        const MobilityReport& mobility = check.mobility;
        std::cout << "coordinates: " << mobility.coordinates << " velocities, " << mobility.constraint_rows
                  << " joint equations, " << mobility.driver_rows << " driver equations\n";
        std::cout << "degrees of freedom (Gruebler count): " << mobility.gruebler_dof << '\n';
        std::cout << "degrees of freedom (rank of C_q): " << mobility.rank_dof << "  (rank " << mobility.rank << ")\n";
        if (mobility.velocity_rows > 0)
            std::cout << "velocity constraints (nonholonomic): " << mobility.velocity_rows
                      << " rows; degrees of freedom of the velocities (rank of [C_q; A]): " << mobility.velocity_dof
                      << '\n';
        if (!mobility.redundant.empty()) {
            std::cout << "redundant constraint rows (" << mobility.redundant.size() << "):\n";
            for (const RowOwner& o : mobility.redundant) std::cout << "  " << o.describe() << '\n';
        }

        if (!model.drivers.empty()) {
            const int drivers = static_cast<int>(model.drivers.size());
            if (check.dependent_driver_rows > 0)
                std::cout << "warning: the drivers are not independent of each other and the joints ("
                          << plural(check.dependent_driver_rows, "redundant driver equation") << ")\n";
            if (check.kinematically_driven)
                std::cout << "kinematically driven: yes (" << plural(drivers, "driver") << (drivers == 1 ? " fixes" : " fix")
                          << " the remaining "
                          << plural(mobility.rank_dof, "degree") << " of freedom)\n";
            else
                std::cout << "kinematically driven: no (" << plural(check.free_dof, "degree")
                          << " of freedom left free; kinematics carries " << (check.free_dof == 1 ? "it" : "them")
                          << " along with minimum-norm steps)\n";
        } else {
            std::cout << "kinematically driven: no (no drivers)\n";
        }
        // the embedding formulation's path (kit/include/mbd/kit/topology.hpp)
        std::cout << "embedding: " << check.embedding.path << " path (" << check.embedding.reason << ")\n";
        return 0;
    };
}

}  // namespace mbd::cli
