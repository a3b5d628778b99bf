#include "statfilter/prepared_series.hpp"

#include <algorithm>

namespace statfilter {

void prepare_tile(double* tile, int64_t frames, int64_t n, const SeriesPrep& prep, double* means) {
    if (prep.repair_nonfinite) repair_nonfinite(tile, frames, n);
    forward_transform(prep.transform, tile, static_cast<size_t>(frames * n));
    std::fill(means, means + n, 0.0);
    for (int64_t f = 0; f < frames; ++f)
        for (int64_t j = 0; j < n; ++j) means[j] += tile[f * n + j];
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
    for (int64_t f = 0; f < F; ++f)
        for (int64_t j = 0; j < t.n; ++j) t.tile[f * t.n + j] += t.means[j];
    inverse_transform(prep_.transform, t.tile.data(), t.tile.size());
    scatter_tile(t.tile.data(), t.range, group_, output);
}

}  // namespace statfilter
