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

// Checks each pattern of the list as the run over input_pattern's frames (--frames, "" = all) will
// write its image result (frame token, format, directory, not a frame of the input or of
// output_pattern: sf_filter_check_image_output), before any work.
void check_save_outputs(const FilterHandle& filter, const std::vector<std::pair<std::string, std::string>>& list,
                        const std::string& input_pattern, const std::string& frames, const std::string& output_pattern);

// Writes each named image result of the list.
void save_image_results(const FilterHandle& filter, const std::vector<std::pair<std::string, std::string>>& list,
                        ProgressLine& progress);

}  // namespace statfilter_cli
