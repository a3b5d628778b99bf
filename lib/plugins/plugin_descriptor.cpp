#include "plugins/plugin_descriptor.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace statfilter {
namespace {

std::string text_or_empty(const char* s) { return s ? s : ""; }

// How many bytes of sf_plugin a plugin of each version has: the fields up to where the next version
// appended its own.
size_t descriptor_size(int abi_version) {
    if (abi_version == 1) return offsetof(sf_plugin, flags);
    return sizeof(sf_plugin);
}

// A parameter entry must hold struct_size, name and type; later fields past its size take defaults.
constexpr size_t kMinParamSize = offsetof(sf_param_info, type) + sizeof(sf_param_type);

sf_param_info read_param_entry(const char* entry, size_t size) {
    sf_param_info p;
    p.struct_size = sizeof p;
    p.name = nullptr;
    p.type = SF_PARAM_STRING;
    p.default_value = "";
    p.description = "";
    p.min = -std::numeric_limits<double>::infinity();
    p.max = std::numeric_limits<double>::infinity();
    p.choices = "";
    std::memcpy(&p, entry, std::min(size, sizeof p));  // memcpy: entries need not be aligned for us
    return p;
}

// The plugin's parameter table as the core's specs. Entries are params[0].struct_size apart, so a
// plugin built against a header whose sf_param_info was smaller or larger still reads right.
std::vector<ParamSpec> param_specs(const sf_plugin& plugin) {
    std::vector<ParamSpec> specs;
    if (plugin.param_count <= 0) return specs;
    if (!plugin.params) throw std::runtime_error("param_count is " + std::to_string(plugin.param_count) + " but params is NULL");
    const size_t stride = plugin.params[0].struct_size;
    if (stride < kMinParamSize)
        throw std::runtime_error("params[0].struct_size is " + std::to_string(stride) + ", less than the " +
                                 std::to_string(kMinParamSize) + " bytes of struct_size, name and type");
    const char* base = reinterpret_cast<const char*>(plugin.params);
    for (int i = 0; i < plugin.param_count; ++i) {
        const sf_param_info p = read_param_entry(base + static_cast<size_t>(i) * stride, stride);
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

std::unique_ptr<PluginDescriptor> read_plugin_descriptor(const sf_plugin& declared) {
    // The version comes first so that it can be read whatever the rest of the struct looks like.
    const int version = declared.abi_version;
    if (version > SF_PLUGIN_ABI_VERSION)
        throw std::runtime_error("plugin ABI version " + std::to_string(version) +
                                 " is newer than this statfilter, which loads versions " +
                                 std::to_string(SF_PLUGIN_ABI_VERSION_FIRST) + " to " + std::to_string(SF_PLUGIN_ABI_VERSION) +
                                 ": update statfilter, or rebuild the plugin against its statfilter_plugin.h");
    if (version < SF_PLUGIN_ABI_VERSION_FIRST)
        throw std::runtime_error("plugin ABI version " + std::to_string(version) + " does not exist (versions start at " +
                                 std::to_string(SF_PLUGIN_ABI_VERSION_FIRST) + ", this statfilter loads up to " +
                                 std::to_string(SF_PLUGIN_ABI_VERSION) + ")");
    sf_plugin p{};  // what the plugin's version lacks stays zero: no flags, no execute_frame
    std::memcpy(&p, &declared, descriptor_size(version));

    auto d = std::make_unique<PluginDescriptor>();
    d->abi_version = version;
    d->name = text_or_empty(p.name);
    d->version = text_or_empty(p.version);
    d->description = text_or_empty(p.description);
    if (p.kind != SF_FILTER_TEMPORAL && p.kind != SF_FILTER_SINGLE_FRAME)
        throw std::runtime_error("unknown filter kind " + std::to_string(p.kind));
    d->kind = static_cast<FilterKind>(p.kind);
    if (!p.create || !p.set_param || !p.release || !(p.execute || p.execute_frame))
        throw std::runtime_error(version == 1 ? "create, set_param, execute and release must all be set"
                                              : "create, set_param, release and execute or execute_frame must be set");
    if (p.execute_frame && p.kind != SF_FILTER_SINGLE_FRAME)
        throw std::runtime_error("execute_frame is for single-frame plugins; a temporal one sets execute");
    d->probe = p.probe;
    d->create = p.create;
    d->set_param = p.set_param;
    d->execute = p.execute;
    d->execute_frame = p.execute_frame;
    d->release = p.release;
    d->thread_safe = (p.flags & SF_PLUGIN_THREAD_SAFE) != 0;
    try {
        d->params = param_specs(p);
    } catch (const std::exception& e) {
        throw std::runtime_error(std::string("bad parameter table: ") + e.what());
    }
    return d;
}

Status plugin_status(sf_status status) {
    const int s = static_cast<int>(status);
    if (s >= static_cast<int>(Status::InvalidArgument) && s <= static_cast<int>(Status::Internal)) return static_cast<Status>(s);
    return Status::Internal;
}

std::string plugin_message(const char* buffer, size_t size) { return std::string(buffer, strnlen(buffer, size)); }

}  // namespace statfilter
