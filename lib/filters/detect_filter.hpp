// The detect filter's parameters as the detection's and the crop windows' options: one reading for
// the filter and for the detect plan's tasks (lib/distributed/detect_tasks.cpp).
#pragma once
#include "statfilter/artifact_detection.hpp"
#include "statfilter/crop_windows.hpp"
#include "statfilter/params.hpp"

namespace statfilter {

DetectOptions detect_options(const ParamSet& params, bool has_noisy);
CropOptions crop_options(const ParamSet& params);

}  // namespace statfilter
