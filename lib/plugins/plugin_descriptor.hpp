// A plugin's sf_plugin, of any plugin ABI version statfilter loads, read into the core's own types.
// What an older version lacks takes its default here, so nothing past this point looks at versions.
// lib/plugins/ is the only part of the core that includes a public C header, and only this one.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "statfilter/filter_registry.hpp"
#include "statfilter/params.hpp"
#include "statfilter/statfilter_plugin.h"

namespace statfilter {

struct PluginDescriptor {
    int abi_version = 0;
    std::string name, version, description;
    FilterKind kind = FilterKind::Temporal;
    std::vector<ParamSpec> params;
    sf_plugin_probe_fn probe = nullptr;  // may be null
    sf_plugin_create_fn create = nullptr;
    sf_plugin_set_param_fn set_param = nullptr;
    sf_plugin_execute_fn execute = nullptr;              // null when only execute_frame is given
    sf_plugin_execute_frame_fn execute_frame = nullptr;  // null: the whole-sequence execute
    sf_plugin_release_fn release = nullptr;
    bool thread_safe = false;
    // Held around every call into a plugin that is not thread-safe, for all its instances.
    mutable std::mutex calls;
};

// Reads every field the plugin's version has and defaults the rest. Throws std::runtime_error saying
// what is wrong (the caller adds the file's name): a version outside SF_PLUGIN_ABI_VERSION_FIRST ..
// SF_PLUGIN_ABI_VERSION, an unknown kind, a missing function, a bad parameter table.
std::unique_ptr<PluginDescriptor> read_plugin_descriptor(const sf_plugin& plugin);

// A status code from a plugin as the core's Status (anything unknown is Internal).
Status plugin_status(sf_status status);

// The message a plugin wrote into a host buffer of `size` bytes, read no further than the buffer
// even when the plugin did not terminate it.
std::string plugin_message(const char* buffer, size_t size);

}  // namespace statfilter
