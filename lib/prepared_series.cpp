#include "statfilter/prepared_series.hpp"

#include <algorithm>

namespace statfilter {

void prepare_tile(double* tile, int64_t frames, int64_t n, const SeriesPrep& prep, double* means) {
    if (prep.repair_nonfinite) repair_nonfinite(tile, frames, n);
    // The tile is larger than the caches: transform a frame's row while it is summed into the means.
    std::fill(means, means + n, 0.0);
    for (int64_t f = 0; f < frames; ++f) {
        double* row = tile + f * n;
        forward_transform(prep.transform, row, static_cast<size_t>(n));
        for (int64_t j = 0; j < n; ++j) means[j] += row[j];
    }
    for (int64_t j = 0; j < n; ++j) means[j] /= static_cast<double>(frames);
    for (int64_t f = 0; f < frames; ++f)
        for (int64_t j = 0; j < n; ++j) tile[f * n + j] -= means[j];
}

PreparedSeries::PreparedSeries(const Sequence& input, ChannelSelection group, const SeriesPrep& prep,
                               double budget_bytes, int buffers_per_tile)
    : input_(input), group_(group), prep_(prep),
      tiles_(make_pixel_tiles(input.shape(), group.count, budget_bytes, buffers_per_tile)) {}

void PreparedSeries::prepare(PixelRange range, PreparedTile& t) const {
    const int64_t F = frames();
    t.range = range;
    t.n = range.size() * group_.count;
    t.tile.resize(static_cast<size_t>(F * t.n));
    t.means.resize(static_cast<size_t>(t.n));
    gather_tile(input_, range, group_, t.tile.data());
    prepare_tile(t.tile.data(), F, t.n, prep_, t.means.data());
}

void PreparedSeries::finish(PreparedTile& t, Sequence& output) const {
    const int64_t F = frames();
    for (int64_t f = 0; f < F; ++f) {
        double* row = t.tile.data() + f * t.n;
        for (int64_t j = 0; j < t.n; ++j) row[j] += t.means[j];
        inverse_transform(prep_.transform, row, static_cast<size_t>(t.n));
    }
    scatter_tile(t.tile.data(), t.range, group_, output);
}

}  // namespace statfilter
