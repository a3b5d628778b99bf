#include "statfilter/prepared_series.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pipeline/parallel.hpp"

namespace statfilter {

namespace {

// prepare_tile's transform and centring for series [j0, j1) of a tile of n series.
void prepare_series(double* tile, int64_t frames, int64_t n, int64_t j0, int64_t j1, const SeriesPrep& prep, double* means) {
    const double scale = prep.scale > 0 ? prep.scale : 1.0;
    // The tile is larger than the caches: transform a frame's row while it is summed into the means.
    std::fill(means + j0, means + j1, 0.0);
    std::vector<uint8_t> constant(static_cast<size_t>(j1 - j0), 1);  // a constant series centres to exact zeros
    for (int64_t f = 0; f < frames; ++f) {
        double* row = tile + f * n;
        forward_transform(prep.transform, scale, row + j0, static_cast<size_t>(j1 - j0));
        for (int64_t j = j0; j < j1; ++j) {
            means[j] += row[j];
            if (row[j] != tile[j]) constant[j - j0] = 0;
        }
    }
    for (int64_t j = j0; j < j1; ++j) means[j] = constant[j - j0] ? tile[j] : means[j] / static_cast<double>(frames);
    for (int64_t f = 0; f < frames; ++f)
        for (int64_t j = j0; j < j1; ++j) tile[f * n + j] -= means[j];
}

}  // namespace

void prepare_tile(double* tile, int64_t frames, int64_t n, const SeriesPrep& prep, double* means) {
    if (prep.repair_nonfinite) repair_nonfinite(tile, frames, n);
    // Series are independent: chunks of them on every core give the same numbers as one pass.
    constexpr int64_t chunk = 8192;
    const Progress none;
    parallel_for((n + chunk - 1) / chunk, resolve_threads(0), [&](int64_t c) {
        prepare_series(tile, frames, n, c * chunk, std::min(n, (c + 1) * chunk), prep, means);
    }, {none});
}

PreparedSeries::PreparedSeries(const Sequence& input, ChannelSelection group, const SeriesPrep& prep,
                               double budget_bytes, int buffers_per_tile, const std::vector<TemporalOutlier>* known,
                               int64_t first_series)
    : input_(input), group_(group), prep_(prep),
      tiles_(make_pixel_tiles(input.shape(), group.count, budget_bytes, buffers_per_tile)) {
    // Measured on the whole group before any pass, so every tiling sees the same scale and fireflies.
    if (!(prep_.scale > 0)) prep_.scale = prep_.scale_factor * transform_level(input, group);
    if (!(prep_.scale > 0) || !std::isfinite(prep_.scale)) prep_.scale = 1.0;
    if (known) {
        const int64_t end = first_series + input.shape().pixels() * group.count;
        auto it = std::lower_bound(known->begin(), known->end(), first_series,
                                   [](const TemporalOutlier& o, int64_t series) { return o.series < series; });
        for (; it != known->end() && it->series < end; ++it) {
            TemporalOutlier o = *it;
            o.series -= first_series;
            outliers_.push_back(o);
        }
    } else if (prep_.outlier_z > 0) {
        OutlierOptions o;
        // Judged relative to the level whatever the transform: in linear units the spread of a few
        // samples per pixel is so skewed that its tail would be taken for fireflies (light lost).
        o.transform = ValueTransform::Log;
        o.scale = prep_.scale;
        o.z = prep_.outlier_z;
        o.repair_nonfinite = prep_.repair_nonfinite;
        o.budget_bytes = budget_bytes;
        outliers_ = find_temporal_outliers(input, group, o);
    }
}

void PreparedSeries::prepare(PixelRange range, PreparedTile& t) const {
    const int64_t F = frames();
    const int64_t n = range.size() * group_.count, first = range.begin * group_.count;
    t.range = range;
    t.n = n;
    t.tile.resize(static_cast<size_t>(F * n));
    t.means.resize(static_cast<size_t>(n));
    gather_tile(input_, range, group_, t.tile.data());
    if (prep_.repair_nonfinite) repair_nonfinite(t.tile.data(), F, n);
    auto it = std::lower_bound(outliers_.begin(), outliers_.end(), first,
                               [](const TemporalOutlier& o, int64_t series) { return o.series < series; });
    for (; it != outliers_.end() && it->series < first + n; ++it) t.tile[it->frame * n + (it->series - first)] = it->value;
    t.linear_means.assign(static_cast<size_t>(n), 0.0);
    t.non_negative.assign(static_cast<size_t>(n), 1);
    for (int64_t f = 0; f < F; ++f)
        for (int64_t j = 0; j < n; ++j) {
            const double v = t.tile[f * n + j];
            t.linear_means[j] += v;
            if (v < 0) t.non_negative[j] = 0;
        }
    for (double& m : t.linear_means) m /= static_cast<double>(F);
    SeriesPrep transform_only = prep_;
    transform_only.repair_nonfinite = false;  // done above, before the fireflies and the linear means
    prepare_tile(t.tile.data(), F, n, transform_only, t.means.data());
}

void PreparedSeries::finish(PreparedTile& t, Sequence& output) const {
    const int64_t F = frames();
    for (int64_t f = 0; f < F; ++f) {
        double* row = t.tile.data() + f * t.n;
        for (int64_t j = 0; j < t.n; ++j) row[j] += t.means[j];
    }
    if (prep_.keep_mean) {
        for (int64_t j = 0; j < t.n; ++j)
            inverse_transform_keeping_mean(prep_.transform, prep_.scale, t.tile.data() + j, F, t.n, t.linear_means[j],
                                           t.non_negative[j] != 0);
    } else {
        inverse_transform(prep_.transform, prep_.scale, t.tile.data(), t.tile.size());
    }
    scatter_tile(t.tile.data(), t.range, group_, output);
}

}  // namespace statfilter
