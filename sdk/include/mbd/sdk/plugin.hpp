// Registering a plugin type.
//
// A plugin library exports, in the ELF section "mbdplug", one symbol per type:
//     mbd_abi<ABI>__<kind>__<type>
// pointing at its factory. The registry reads these names from the file with
// Boost.DLL's library_info, without loading it, so it knows every library's
// kind, type names and ABI version, and opens a library only when a scene
// uses one of its types. Usage, in a plugin's single source file:
//
//     std::unique_ptr<mbd::Joint> make_coupler(const mbd::JointSpec& spec) { ... }
//     MBD_JOINT_PLUGIN(coupler, make_coupler)
//
// Type names are lowercase C identifiers (letters, digits, underscores).
#pragma once

#include <mbd/sdk/force.hpp>
#include <mbd/sdk/joint.hpp>

#include <boost/dll/alias.hpp>

#include <memory>

// The element plugins' ABI (joint, force, body). Bumped whenever a type in the SDK headers
// changes layout or meaning. The formulation kit has its own (kit plugin.hpp, MBD_KIT_ABI_VERSION).
#define MBD_ABI_VERSION 11

namespace mbd {

using JointFactory = std::unique_ptr<Joint>(const JointSpec&);
using ForceFactory = std::unique_ptr<Force>(const ForceSpec&);

}  // namespace mbd

#define MBD_PLUGIN_CAT5_(a, b, c, d, e) a##b##c##d##e
#define MBD_PLUGIN_CAT5(a, b, c, d, e) MBD_PLUGIN_CAT5_(a, b, c, d, e)
#define MBD_PLUGIN_SYMBOL(kind, type) MBD_PLUGIN_CAT5(mbd_abi, MBD_ABI_VERSION, __, kind, MBD_PLUGIN_CAT5(__, type, , , ))

#define MBD_REGISTER_PLUGIN(kind, type, factory) \
    BOOST_DLL_ALIAS_SECTIONED(factory, MBD_PLUGIN_SYMBOL(kind, type), mbdplug)

#define MBD_JOINT_PLUGIN(type, factory) MBD_REGISTER_PLUGIN(joint, type, factory)
#define MBD_FORCE_PLUGIN(type, factory) MBD_REGISTER_PLUGIN(force, type, factory)
