// URDF through liburdfdom (urdf::parseURDFFile), the ROS parser: links with their <inertial>,
// joints with their origin and axis, walked from the root link at zero joint positions.
// TinyXML, the XML parser urdfdom itself uses, locates elements (file:line in the scene's
// comments and in errors) and checks the link tree before urdfdom walks it.
#pragma once

#include <mbd/import/source_tree.hpp>

#include <filesystem>

namespace mbd::import {

// Throws InputError naming the element: malformed XML (with its line), a link that is the child
// of two joints or a cycle of joints, an unknown joint type (urdfdom's message), a missing link.
SourceTree read_urdf(const std::filesystem::path& file);

}  // namespace mbd::import
