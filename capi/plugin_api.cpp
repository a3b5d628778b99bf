// sf_filter_info_*: what the registry knows about each filter, built-in or plugin.
#include <cstring>

#include "api_guard.hpp"
#include "options.hpp"
#include "statfilter/filter_registry.hpp"

using namespace statfilter;
using namespace statfilter::capi;

namespace {

void fill(const FilterEntry& e, sf_filter_info* info) {
    sf_filter_info& out = require_versioned_out(info, "info");
    static const std::string builtin = "built-in";
    sf_filter_info full;
    full.name = e.name.c_str();  // entries, and so their strings, live until exit
    full.description = e.description.c_str();
    full.kind = static_cast<sf_filter_kind>(e.kind);
    full.origin = e.origin.empty() ? builtin.c_str() : e.origin.c_str();
    full.version = e.origin.empty() ? sf_version_string() : e.version.c_str();
    full.available = e.available() ? 1 : 0;
    full.problem = e.problem.c_str();
    write_versioned(out, full);
}

}  // namespace

extern "C" {

void sf_filter_info_init(sf_filter_info* info) {
    if (!info) return;
    std::memset(info, 0, sizeof *info);
    info->struct_size = sizeof *info;
}

int sf_filter_info_count(void) {
    try {
        return static_cast<int>(all_filters().size());
    } catch (...) {
        return 0;
    }
}

sf_status sf_filter_info_at(int index, sf_filter_info* info) {
    return guarded([&] {
        const auto filters = all_filters();
        if (index < 0 || static_cast<size_t>(index) >= filters.size())
            throw Error(Status::InvalidArgument, "filter index " + std::to_string(index) + " out of range (" +
                                                     std::to_string(filters.size()) + " filters)");
        fill(*filters[static_cast<size_t>(index)], info);
    });
}

sf_status sf_filter_info_get(const char* name, sf_filter_info* info) {
    return guarded([&] { fill(find_filter(require_string(name, "name")), info); });
}

}  // extern "C"
