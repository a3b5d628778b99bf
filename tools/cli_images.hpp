// Image results of filters: saving them, and false-colour previews for people to look at.
#pragma once
#include <string>

#include "cli_common.hpp"

namespace statfilter_cli {

// Writes the filter's image result `name` to pattern (EXR float, or PNG by extension: false colour).
void save_image_result(const FilterHandle& filter, const std::string& name, const std::string& pattern,
                       ProgressLine& progress);

// "a=x.exr,b=y.####.exr" -> writes each named image result.
void save_image_results(const FilterHandle& filter, const std::string& list, ProgressLine& progress);

}  // namespace statfilter_cli
