// Image results of filters: saving them, and false-colour previews for people to look at.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "cli_common.hpp"

namespace statfilter_cli {

// Writes the filter's image result `name` to pattern (EXR float, or PNG by extension: false colour).
void save_image_result(const FilterHandle& filter, const std::string& name, const std::string& pattern,
                       ProgressLine& progress);

// "a=x.exr,b=y.####.exr" -> (name, pattern) pairs; a UsageError for anything else.
std::vector<std::pair<std::string, std::string>> parse_save_list(const std::string& list);

// Throws UsageError unless the filter can produce every image result the list names (before any work).
void check_save_list(const FilterHandle& filter, const std::string& method,
                     const std::vector<std::pair<std::string, std::string>>& list);

// Writes each named image result of the list.
void save_image_results(const FilterHandle& filter, const std::vector<std::pair<std::string, std::string>>& list,
                        ProgressLine& progress);

}  // namespace statfilter_cli
