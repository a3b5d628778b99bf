// The plugins found so far. Each file is loaded at most once per process and its entry kept until
// exit, so references to entries (and their name strings) stay valid.
#pragma once
#include <string>
#include <vector>

#include "plugins/plugin_search.hpp"
#include "statfilter/filter_registry.hpp"

namespace statfilter {

class PluginRegistry {
public:
    // The plugin for a filter name: the first statfilter_NAME.so on the search path, loaded on first
    // use. nullptr when no directory has one.
    virtual const FilterEntry* find(const std::string& name) = 0;
    // Every plugin file on the search path (first directory wins for a name), usable or not.
    virtual std::vector<const FilterEntry*> all() = 0;
    virtual ~PluginRegistry() = default;
};

PluginRegistry& plugin_registry();

}  // namespace statfilter
