// The key descriptions plugin types export beside their factories (sdk plugin_keys.hpp),
// read by the host: the scene loader's key messages, `mbd plugin check`'s test scenes and
// `mbd plugins --keys`.
#pragma once

#include <mbd/registry.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <string>
#include <vector>

namespace mbd {

// The description of a usable type, or nullptr when the type is unknown, its library does not
// load, or it exports no description (a plugin built before descriptions existed). Opens the
// type's library once per process and keeps it open, so the pointer stays valid.
const PluginDescription* plugin_description(const Registry& registry, const std::string& kind,
                                            const std::string& type);

// The names of a description's keys, in its order.
std::vector<std::string> key_names(const PluginDescription& description);

// A key's default as a reader sees it: the default text, or "required".
std::string key_default(const PluginKey& key);

}  // namespace mbd
