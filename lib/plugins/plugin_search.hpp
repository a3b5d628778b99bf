// Where filter plugins are looked for, and how a filter's name maps to a file name.
#pragma once
#include <string>
#include <vector>

namespace statfilter {

// Each directory of $STATFILTER_PLUGIN_PATH (colon-separated, in order), then the directory that
// holds libstatfilter itself (found with dladdr), without duplicates.
std::vector<std::string> plugin_directories();
// The same as text for error messages.
std::string plugin_search_text();

// statfilter_NAME.so
std::string plugin_file_name(const std::string& filter_name);
// The filter name a plugin file name stands for; "" when the name is not of that form.
std::string plugin_name_from_file(const std::string& file_name);
// Letters, digits, '-', '_' and '.', not starting with '.': a name that cannot reach outside a directory.
bool valid_plugin_name(const std::string& name);

}  // namespace statfilter
