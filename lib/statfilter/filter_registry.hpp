// The one place filters are found by name: the built-ins listed in filter_registry.cpp, then the
// plugins found on the plugin search path (lib/plugins/), through the same entries.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "statfilter/filter.hpp"

namespace statfilter {

// Single-frame filters work frame by frame, so they can run before a temporal filter (prefilter).
enum class FilterKind { Temporal = 0, SingleFrame = 1 };

struct FilterEntry {
    FilterEntry() = default;
    // The built-in table's form: {name, description, factory} or {..., FilterKind::SingleFrame}.
    FilterEntry(std::string name_, std::string description_, std::function<std::unique_ptr<Filter>()> create_,
                FilterKind kind_ = FilterKind::Temporal)
        : name(std::move(name_)), description(std::move(description_)), create(std::move(create_)), kind(kind_) {}

    std::string name;
    std::string description;
    std::function<std::unique_ptr<Filter>()> create;
    FilterKind kind = FilterKind::Temporal;
    std::string origin;   // empty for built-ins; the plugin file's path otherwise
    std::string version;  // the plugin's own version (built-ins: the library's)
    std::string problem;  // non-empty: found but unusable (create throws with this message)
    bool available() const { return problem.empty(); }
};

// The built-in filters.
const std::vector<FilterEntry>& filter_registry();
// Built-ins, then every plugin on the search path (all loaded once), usable or not. The entries
// live until exit.
std::vector<const FilterEntry*> all_filters();
// Only the filters that can be created here.
std::vector<const FilterEntry*> available_filters();
// Built-in or plugin (loaded on first use). Throws Error(NotFound) naming the known filters.
const FilterEntry& find_filter(const std::string& name);
// Throws the plugin's own error (naming its file) when it exists but cannot be used.
std::unique_ptr<Filter> create_filter(const std::string& name);

}  // namespace statfilter
