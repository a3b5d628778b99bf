// Temporal work sees the data as a matrix with one row per (pixel, channel) time series and one
// column per frame. Sequences are stored frame by frame, so temporal filters walk them in tiles:
// a range of pixels x all frames, gathered into a double F x n buffer (frame-major, n series).
// The tile size follows a memory budget, which bounds memory for any frame size.
#pragma once
#include <cstdint>
#include <vector>

#include "statfilter/sequence.hpp"

namespace statfilter {

struct PixelRange {
    int64_t begin = 0, end = 0;  // pixel indices in row-major order, end exclusive
    int64_t size() const { return end - begin; }
};

// Which channels a tile holds: all of them interleaved (channel fastest), or one.
struct ChannelSelection {
    int64_t first = 0, count = 1;
    static ChannelSelection all(const Shape& s) { return {0, s.channels}; }
    static ChannelSelection one(int64_t c) { return {c, 1}; }
};

// Splits the pixels into ranges whose F x n double buffers (times buffers_per_tile) fit the budget.
std::vector<PixelRange> make_pixel_tiles(const Shape& shape, int64_t channels_per_pixel, double budget_bytes,
                                         int buffers_per_tile);

// tile[f * n + j] = sample of series j in frame f, n = range.size() * channels.count.
void gather_tile(const Sequence& seq, PixelRange range, ChannelSelection channels, double* tile);
// The inverse of gather_tile, rounding to float and saturating at the float range.
void scatter_tile(const double* tile, PixelRange range, ChannelSelection channels, Sequence& seq);

}  // namespace statfilter
