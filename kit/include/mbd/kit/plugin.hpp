// Registering a plugin of the formulation kit: kinds formulation, statics and inverse
// (MBD_FORMULATION_PLUGIN, MBD_STATICS_PLUGIN, MBD_INVERSE_PLUGIN). The symbol is the element
// plugins' (sdk plugin.hpp: mbd_abi<ABI>__<kind>__<type>) with the kit's own ABI version, so
// that a change of the kit does not bump the ABI of the joint, force and body plugins. The kit
// is built on the SDK's types (a System holds Joints and Forces): a change of those bumps both.
#pragma once

#include <mbd/sdk/plugin.hpp>

#include <string>

// Bumped whenever a type in the kit headers (kit/include/mbd/kit) changes layout or meaning.
#define MBD_KIT_ABI_VERSION 3  // 2: Formulation::index3_problem() for supports_index3(); System::joint_material_frame(); 3: System::driver_material_frame()

#define MBD_KIT_PLUGIN_SYMBOL(kind, type) \
    MBD_PLUGIN_CAT5(mbd_abi, MBD_KIT_ABI_VERSION, __, kind, MBD_PLUGIN_CAT5(__, type, , , ))
#define MBD_REGISTER_KIT_PLUGIN(kind, type, factory) \
    BOOST_DLL_ALIAS_SECTIONED(factory, MBD_KIT_PLUGIN_SYMBOL(kind, type), mbdplug)

namespace mbd {

// The plugin kinds built on the kit; every other kind (joint, force, body) is an element
// plugin of the SDK's ABI.
inline bool is_kit_kind(const std::string& kind) {
    return kind == "formulation" || kind == "statics" || kind == "inverse";
}

// The ABI this host speaks for plugins of a kind.
inline int host_abi(const std::string& kind) { return is_kit_kind(kind) ? MBD_KIT_ABI_VERSION : MBD_ABI_VERSION; }

}  // namespace mbd
