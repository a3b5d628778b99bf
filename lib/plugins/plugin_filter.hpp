// A plugin's filter behind the core's Filter interface: parameters checked against the plugin's own
// table by the core, then handed to the plugin as text before each run; frames run through the
// plugin's execute_frame by the host's loop when it has one, else its whole-sequence execute.
#pragma once
#include <memory>
#include <string>

#include "plugins/plugin_descriptor.hpp"
#include "statfilter/filter.hpp"

namespace statfilter {

// Throws Error with the plugin's message when its create fails.
std::unique_ptr<Filter> make_plugin_filter(std::shared_ptr<const PluginDescriptor> plugin, const std::string& path);

}  // namespace statfilter
