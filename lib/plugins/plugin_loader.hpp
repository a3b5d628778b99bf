// Loading one plugin file: dlopen, the entry symbol, its descriptor (plugin_descriptor.hpp), the probe
// and one instance made as a check.
#pragma once
#include <string>

#include "statfilter/filter_registry.hpp"

namespace statfilter {

// Never throws: a file that cannot be used gives an entry whose problem says why, naming the file,
// and whose create() throws that error.
FilterEntry load_plugin(const std::string& path, const std::string& expected_name);

}  // namespace statfilter
