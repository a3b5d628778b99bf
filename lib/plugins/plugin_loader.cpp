#include "plugins/plugin_loader.hpp"

#include <dlfcn.h>

#include <memory>

#include "plugins/plugin_descriptor.hpp"
#include "plugins/plugin_filter.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

// A plugin that cannot be used: listed with the reason, and creating it throws the reason.
FilterEntry unusable(FilterEntry entry, Status status, const std::string& problem) {
    entry.problem = problem;
    entry.create = [status, problem]() -> std::unique_ptr<Filter> { throw Error(status, problem); };
    return entry;
}

}  // namespace

FilterEntry load_plugin(const std::string& path, const std::string& expected_name) {
    FilterEntry entry;
    entry.name = expected_name;
    entry.origin = path;
    const std::string where = "plugin " + path + ": ";

    dlerror();
    void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        const char* why = dlerror();
        return unusable(entry, Status::Io, where + "cannot load: " + (why ? why : ""));
    }
    // Never unloaded: filters and their parameter texts point into the library until exit.
    void* symbol = dlsym(library, SF_PLUGIN_ENTRY);
    if (!symbol)
        return unusable(entry, Status::Unsupported,
                        where + "no function " SF_PLUGIN_ENTRY " (not a statfilter plugin, or not exported)");
    const sf_plugin* declared = reinterpret_cast<sf_plugin_entry_fn>(symbol)();
    if (!declared) return unusable(entry, Status::Unsupported, where + SF_PLUGIN_ENTRY "() returned NULL");
    std::shared_ptr<const PluginDescriptor> plugin;
    try {
        plugin = read_plugin_descriptor(*declared);
    } catch (const std::exception& e) {
        return unusable(entry, Status::Unsupported, where + e.what());
    }
    entry.description = plugin->description;
    entry.version = plugin->version;
    entry.kind = plugin->kind;
    if (plugin->name != expected_name)
        return unusable(entry, Status::Unsupported,
                        where + "declares filter '" + plugin->name + "', but its file name says '" + expected_name + "'");
    if (plugin->probe) {
        char message[2048] = "";
        const sf_status status = plugin->probe(message, sizeof message);
        if (status != SF_OK)
            return unusable(entry, plugin_status(status),
                            expected_name + " (" + path + ") cannot run here: " + plugin_message(message, sizeof message));
    }
    // One instance made and released: a plugin that cannot create one here (no device, no licence)
    // is listed as unavailable with its reason, instead of failing whoever lists or describes filters.
    try {
        make_plugin_filter(plugin, path);
    } catch (const Error& e) {
        return unusable(entry, e.status(), expected_name + " (" + path + ") cannot create a filter here: " + e.what());
    }
    entry.create = [plugin, path]() { return make_plugin_filter(plugin, path); };
    return entry;
}

}  // namespace statfilter
