// The hybrid's analysis (filters/hybrid_stage.hpp) as files in a directory, so that a plan's frame
// tasks can run the window on other processes or nodes: the frames it parked (I_T, the first pass,
// the flow guides) as float32 files, frame after frame as the scratch held them; the grown moving
// weight (float32 per pixel) and the fireflies (frame, sample, value) in binary; the numbers, and
// the caller's own members, in analysis.json. Nothing here is atomic: the caller writes a temporary
// directory and renames it into place.
#pragma once
#include <string>

#include "filters/hybrid_stage.hpp"
#include "statfilter/json.hpp"

namespace statfilter {

// extra_members: JSON object members ("key": value, ...) the caller reads back (may be empty).
void save_hybrid_analysis(const HybridAnalysis& analysis, const Shape& shape, const std::string& dir,
                          const std::string& extra_members);
// The analysis saved in dir for frames of `shape`, its frames read from the files as they are
// needed; `json` (optional) receives analysis.json. Names the file that is missing or does not fit.
HybridAnalysis load_hybrid_analysis(const Shape& shape, const Sequence& attributes, const std::string& dir,
                                    JsonValue* json);

}  // namespace statfilter
