// A plugin type's own description of its scene keys, exported beside its factory.
//
// Each key has a name, a meaning, its default (or none: required) and an example value
// (YAML text). The host reads the description to
//   - build a valid test scene for `mbd plugin check` with no flags (the examples of the
//     required keys, and of the optional keys marked `in_check`; two moving bodies for a
//     two-body element),
//   - tell a key no type accepts ("unknown key ...; valid keys: ...") from a documented
//     key that is wrong where it stands ("... is not used here"),
//   - print the key table (`mbd plugins --keys TYPE`), which a test compares with
//     docs/scene-format.md.
// Usage, in a plugin's source, next to MBD_JOINT_PLUGIN / MBD_FORCE_PLUGIN:
//
//     const mbd::PluginKey screw_keys[] = {
//         {"pitch", "travel along the axis per revolution (m), non-zero", nullptr, "0.02"},
//         {}};  // a key without a name ends the list
//     MBD_JOINT_KEYS(screw, "a helical joint", mbd::kTwoBodies, mbd::kSpatialOnly, screw_keys)
//
// The description is a separate exported symbol, mbd_keys<KEYS_VERSION>__<kind>__<type>, in
// the same ELF section "mbdplug": a library without one still loads and works (the plugin
// check then needs --params, as before), so adding it does not change the plugin ABI. Only
// plain C types cross the boundary.
#pragma once

#include <boost/dll/alias.hpp>

#include <cstring>

// Bumped whenever PluginKey or PluginDescription changes layout or meaning.
#define MBD_KEYS_VERSION 1

namespace mbd {

struct PluginKey {
    const char* name = nullptr;           // nullptr ends a key list
    const char* meaning = nullptr;        // one line: what it is, units, range, when it applies
    const char* default_value = nullptr;  // nullptr: the key is required (or one of a required pair)
    const char* example = nullptr;        // a valid YAML value (planar, or both dimensions)
    const char* example_spatial = nullptr;  // a spatial scene's value when it differs (vector sizes)
    bool in_check = false;                // `mbd plugin check` sets this optional key to its example too
};

// Which scene dimensions a type works in.
enum PluginDimensions : int { kPlanarOnly = 1, kSpatialOnly = 2, kPlanarAndSpatial = 3 };
// How many bodies an element of the type connects (`body:` or `bodies: [a, b]`); 0 for the
// core's gravity, which acts on every body and has no scene entry.
enum PluginBodies : int { kEveryBody = 0, kOneBody = 1, kTwoBodies = 2 };

struct PluginDescription {
    const char* summary = nullptr;
    int bodies = kTwoBodies;
    int dimensions = kPlanarAndSpatial;
    const PluginKey* keys = nullptr;  // ends with a key without a name

    int key_count() const {
        int n = 0;
        while (keys && keys[n].name) ++n;
        return n;
    }
    const PluginKey* find(const char* name) const;
};

inline const PluginKey* PluginDescription::find(const char* name) const {
    for (int k = 0; k < key_count(); ++k)
        if (std::strcmp(keys[k].name, name) == 0) return &keys[k];
    return nullptr;
}

using DescribePlugin = const PluginDescription&();

}  // namespace mbd

#define MBD_KEYS_CAT5_(a, b, c, d, e) a##b##c##d##e
#define MBD_KEYS_CAT5(a, b, c, d, e) MBD_KEYS_CAT5_(a, b, c, d, e)
#define MBD_KEYS_SYMBOL(kind, type) MBD_KEYS_CAT5(mbd_keys, MBD_KEYS_VERSION, __, kind, MBD_KEYS_CAT5(__, type, , , ))

#define MBD_REGISTER_KEYS(kind, type, summary, bodies, dimensions, keys)                          \
    const mbd::PluginDescription& MBD_KEYS_CAT5(mbd_describe_, kind, _, type, )() {                \
        static const mbd::PluginDescription description{summary, bodies, dimensions, keys};        \
        return description;                                                                        \
    }                                                                                              \
    BOOST_DLL_ALIAS_SECTIONED(MBD_KEYS_CAT5(mbd_describe_, kind, _, type, ), MBD_KEYS_SYMBOL(kind, type), mbdplug)

#define MBD_JOINT_KEYS(type, summary, bodies, dimensions, keys) \
    MBD_REGISTER_KEYS(joint, type, summary, bodies, dimensions, keys)
#define MBD_FORCE_KEYS(type, summary, bodies, dimensions, keys) \
    MBD_REGISTER_KEYS(force, type, summary, bodies, dimensions, keys)
