// Parts of a frame source as sources of their own, for tile tasks: rows [y0, y1) of every frame (a
// band of full-width rows), or frames [first, last) whole. Borrowed: the base outlives them.
#pragma once
#include <cstdint>
#include <memory>

#include "pipeline/frame_source.hpp"

namespace statfilter {

std::unique_ptr<FrameSource> row_window(const FrameSource& base, int64_t y0, int64_t y1);
std::unique_ptr<FrameSource> frame_range(const FrameSource& base, int64_t first, int64_t last);
// The names, frame numbers and metadata of frames [first, last) of `attributes` (shape only).
std::unique_ptr<Sequence> frame_range_attributes(const Sequence& attributes, int64_t first, int64_t last);

}  // namespace statfilter
