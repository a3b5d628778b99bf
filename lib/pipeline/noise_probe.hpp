// Reads the few rows the noise-in-time check needs from a frame source (statfilter/noise_in_time.hpp).
#pragma once
#include <string>

#include "pipeline/frame_source.hpp"
#include "statfilter/noise_in_time.hpp"

namespace statfilter {

// Up to three pairs of consecutive frames (at the start, the middle and the end of the shot), each
// on at most kNoiseProbeRows rows around the middle of the frame: a few frames' worth of a band,
// read before the work starts. Not measured (ratio 1) for a shot of fewer than 2 frames.
constexpr int64_t kNoiseProbeRows = 128;
NoiseInTime probe_noise_in_time(const FrameSource& source);

// The warning a run reports (result "warning") when the noise is the same in every frame, else "".
std::string same_noise_warning(const NoiseInTime& noise);

}  // namespace statfilter
