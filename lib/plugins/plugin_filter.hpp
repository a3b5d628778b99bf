// A plugin's filter behind the core's Filter interface: parameters checked against the plugin's own
// table by the core, then handed to the plugin as text before each run.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "statfilter/filter.hpp"
#include "statfilter/statfilter.h"

namespace statfilter {

std::unique_ptr<Filter> make_plugin_filter(const sf_plugin* plugin, const std::string& path, std::vector<ParamSpec> specs);

// A status code from a plugin as the core's Status (anything unknown is Internal).
Status plugin_status(sf_status status);

// The message a plugin wrote into a host buffer of `size` bytes, read no further than the buffer
// even when the plugin did not terminate it.
std::string plugin_message(const char* buffer, size_t size);

}  // namespace statfilter
