// The re-render list: a per-frame pixel mask becomes a few rectangles (crop windows) a renderer can
// render, covering every flagged pixel with little waste, written and read as JSON.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "statfilter/sequence.hpp"

namespace statfilter {

// Pixel rectangle: columns x .. x + width - 1, rows y .. y + height - 1, row 0 at the top (the
// order the frames are stored in).
struct CropWindow {
    int64_t x = 0, y = 0, width = 0, height = 0;
    int64_t area() const { return width * height; }
    bool operator==(const CropWindow& o) const {
        return x == o.x && y == o.y && width == o.width && height == o.height;
    }
};

struct FrameCrops {
    int64_t frame = 0;    // frame number, as on disk
    int64_t flagged = 0;  // flagged pixels in this frame
    std::vector<CropWindow> windows;
};

struct CropOptions {
    int64_t padding = 1;       // pixels added around the flagged pixels on every side
    int64_t min_size = 4;      // windows narrower or lower than this grow to it (within the image)
    // The render cost: the pixels one more renderer start-up is worth (scene load, BVH build, kernel
    // set-up, farm scheduling, as the time of rendering that many pixels). Two windows merge when
    // the pixels their bounding box adds cost at most one start-up (extra <= window_cost); 0 merges
    // only windows that overlap or whose union adds no pixel. See docs/rerender.md for how to measure it for a renderer.
    int64_t window_cost = 64;
};

struct CropPlan {
    int64_t width = 0, height = 0, frame_count = 0;
    CropOptions options;
    std::vector<FrameCrops> frames;  // only frames with windows, ascending by frame number
    int64_t flagged() const;
    int64_t window_pixels() const;
    int64_t window_count() const;
    // What re-rendering the plan costs, in pixels: window_pixels() + window_count() x window_cost
    // (each render's start-up counted as window_cost pixels), the total the merging lowers.
    int64_t cost_pixels() const;
};

// Windows covering every non-zero pixel of one mask (height x width, row-major): the flagged pixels
// grouped by connectivity after dilating by the padding, each group's bounding box, grown to the
// minimum size, then merged pairwise (overlapping windows always, others while the union adds at
// most window_cost pixels, the cheapest merge first: each such merge saves one start-up for fewer
// extra pixels than it is worth, so cost_pixels never rises; a frame with more than 512 windows has
// those in the same grid cell merged first, whatever they cost). Sorted by row, then column.
std::vector<CropWindow> cover_mask(const std::vector<uint8_t>& mask, int64_t height, int64_t width,
                                   const CropOptions& options);

// Every frame of a mask sequence; a pixel is flagged when any channel is non-zero.
CropPlan make_crop_plan(const Sequence& mask, const CropOptions& options);

std::string crop_plan_to_json(const CropPlan& plan);

// Parses and validates (format, version, integer fields, windows inside the image, no frame twice);
// throws Error(InvalidArgument) with a message that names the offending frame and window.
CropPlan crop_plan_from_json(const std::string& text);

// Throws Error(InvalidArgument) unless the plan was made for width x height frames and each of its
// frames is one of frame_numbers.
void check_crop_plan(const CropPlan& plan, int64_t width, int64_t height, const std::vector<int64_t>& frame_numbers);

}  // namespace statfilter
