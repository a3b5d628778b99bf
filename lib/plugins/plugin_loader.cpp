#include "plugins/plugin_loader.hpp"

#include <dlfcn.h>

#include <algorithm>

#include "plugins/plugin_filter.hpp"
#include "statfilter/error.hpp"
#include "statfilter/statfilter.h"

namespace statfilter {
namespace {

// A plugin that cannot be used: listed with the reason, and creating it throws the reason.
FilterEntry unusable(FilterEntry entry, Status status, const std::string& problem) {
    entry.problem = problem;
    entry.create = [status, problem]() -> std::unique_ptr<Filter> { throw Error(status, problem); };
    return entry;
}

std::string text_or_empty(const char* s) { return s ? s : ""; }

// The plugin's parameter table as the core's specs. Entries are params[0].struct_size apart, so a
// plugin built against a header whose sf_param_info had grown still reads right.
std::vector<ParamSpec> param_specs(const sf_plugin& plugin) {
    std::vector<ParamSpec> specs;
    if (plugin.param_count <= 0) return specs;
    if (!plugin.params) throw std::runtime_error("param_count is " + std::to_string(plugin.param_count) + " but params is NULL");
    const size_t stride = plugin.params[0].struct_size;
    if (stride < sizeof(sf_param_info))
        throw std::runtime_error("params[0].struct_size is " + std::to_string(stride) + ", less than sizeof(sf_param_info)");
    for (int i = 0; i < plugin.param_count; ++i) {
        const auto& p = *reinterpret_cast<const sf_param_info*>(reinterpret_cast<const char*>(plugin.params) + i * stride);
        if (!p.name || !*p.name) throw std::runtime_error("parameter " + std::to_string(i) + " has no name");
        ParamSpec s;
        s.name = p.name;
        if (p.type != SF_PARAM_INT && p.type != SF_PARAM_FLOAT && p.type != SF_PARAM_STRING)
            throw std::runtime_error("parameter '" + s.name + "' has an unknown type");
        s.type = static_cast<ParamType>(p.type);
        s.default_value = text_or_empty(p.default_value);
        s.description = text_or_empty(p.description);
        if (s.type != ParamType::String) {
            s.min = p.min;
            s.max = p.max;
        }
        const std::string choices = text_or_empty(p.choices);
        for (size_t start = 0; !choices.empty() && start <= choices.size();) {
            const size_t comma = std::min(choices.find(',', start), choices.size());
            s.choices.push_back(choices.substr(start, comma - start));
            start = comma + 1;
        }
        specs.push_back(std::move(s));
    }
    ParamSet check(specs);  // every default must satisfy its own spec
    return specs;
}

}  // namespace

FilterEntry load_plugin(const std::string& path, const std::string& expected_name) {
    FilterEntry entry;
    entry.name = expected_name;
    entry.origin = path;
    const std::string where = "plugin " + path + ": ";

    dlerror();
    void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) return unusable(entry, Status::Io, where + "cannot load: " + text_or_empty(dlerror()));
    // Never unloaded: filters and their parameter texts point into the library until exit.
    void* symbol = dlsym(library, SF_PLUGIN_ENTRY);
    if (!symbol)
        return unusable(entry, Status::Unsupported,
                        where + "no function " SF_PLUGIN_ENTRY " (not a statfilter plugin, or not exported)");
    const sf_plugin* plugin = reinterpret_cast<sf_plugin_entry_fn>(symbol)();
    if (!plugin) return unusable(entry, Status::Unsupported, where + SF_PLUGIN_ENTRY "() returned NULL");
    // The version comes first so that it can be read whatever the rest of the struct looks like.
    if (plugin->abi_version != SF_PLUGIN_ABI_VERSION)
        return unusable(entry, Status::Unsupported,
                        where + "plugin ABI version " + std::to_string(plugin->abi_version) + ", but this statfilter loads version " + std::to_string(SF_PLUGIN_ABI_VERSION) +
                            ": rebuild the plugin against this statfilter.h");

    entry.description = text_or_empty(plugin->description);
    entry.version = text_or_empty(plugin->version);
    if (plugin->kind != SF_FILTER_TEMPORAL && plugin->kind != SF_FILTER_SINGLE_FRAME)
        return unusable(entry, Status::Unsupported, where + "unknown filter kind " + std::to_string(plugin->kind));
    entry.kind = static_cast<FilterKind>(plugin->kind);
    if (text_or_empty(plugin->name) != expected_name)
        return unusable(entry, Status::Unsupported,
                        where + "declares filter '" + text_or_empty(plugin->name) + "', but its file name says '" +
                            expected_name + "'");
    if (!plugin->create || !plugin->set_param || !plugin->execute || !plugin->release)
        return unusable(entry, Status::Unsupported, where + "create, set_param, execute and release must all be set");
    std::vector<ParamSpec> specs;
    try {
        specs = param_specs(*plugin);
    } catch (const std::exception& e) {
        return unusable(entry, Status::Unsupported, where + "bad parameter table: " + e.what());
    }
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
        make_plugin_filter(plugin, path, specs);
    } catch (const Error& e) {
        return unusable(entry, e.status(), expected_name + " (" + path + ") cannot create a filter here: " + e.what());
    }
    entry.create = [plugin, path, specs]() { return make_plugin_filter(plugin, path, specs); };
    return entry;
}

}  // namespace statfilter
