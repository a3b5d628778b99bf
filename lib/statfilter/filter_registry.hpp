// The one place filters are found by name: built-ins register here, and so will plugins.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "statfilter/filter.hpp"

namespace statfilter {

struct FilterEntry {
    std::string name;
    std::string description;
    std::function<std::unique_ptr<Filter>()> create;
};

const std::vector<FilterEntry>& filter_registry();
// Throws Error(NotFound) naming the known filters.
const FilterEntry& find_filter(const std::string& name);
std::unique_ptr<Filter> create_filter(const std::string& name);

}  // namespace statfilter
