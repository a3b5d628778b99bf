// Rows of every frame of a source as one sequence (a band of scanlines): the passes over the shot
// that need every frame at once (the Gram, the motion statistics) walk the shot in bands of these.
#pragma once
#include <memory>
#include <vector>

#include "pipeline/frame_source.hpp"
#include "statfilter/progress.hpp"

namespace statfilter {

// Rows [y0, y1) of every frame: a view of the source's memory when it holds the shot, else read into
// buffer (frames in parallel on `threads` threads).
std::unique_ptr<Sequence> band_view(const FrameSource& source, int64_t y0, int64_t y1, std::vector<float>& buffer,
                                    int threads, const ProgressSpan& progress);

// Rows [y0, y1) of a band that starts at row y0 - top: a view into it, no copy.
std::unique_ptr<Sequence> rows_of_band(const Sequence& band, int64_t top, int64_t rows);

}  // namespace statfilter
