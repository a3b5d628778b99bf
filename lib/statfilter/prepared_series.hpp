// The time series of one channel group, ready for temporal work: gathered tile by tile, repaired,
// transformed and centred. Filters make several passes (basis, then reconstruction); when the whole
// group fits in one tile of the memory budget it is prepared once and kept for every pass.
#pragma once
#include <memory>
#include <vector>

#include "statfilter/nonfinite.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/time_series_tiles.hpp"
#include "statfilter/value_transform.hpp"

namespace statfilter {

// How a gathered tile becomes the centred series the basis describes.
struct SeriesPrep {
    ValueTransform transform = ValueTransform::None;
    bool repair_nonfinite = false;
};

// Repairs and transforms a gathered F x n tile, then centres every series; its means go to means[n].
void prepare_tile(double* tile, int64_t frames, int64_t n, const SeriesPrep& prep, double* means);

// One prepared tile: tile[f * n + j] is series j in frame f, centred; means[j] its mean.
struct PreparedTile {
    PixelRange range;
    int64_t n = 0;
    std::vector<double> tile, means;
};

class PreparedSeries {
public:
    // buffers_per_tile: how many F x n double buffers a pass holds at once (for the budget).
    PreparedSeries(const Sequence& input, ChannelSelection group, const SeriesPrep& prep, double budget_bytes,
                   int buffers_per_tile);

    int64_t frames() const { return input_.shape().frames; }
    const Shape& shape() const { return input_.shape(); }
    ChannelSelection group() const { return group_; }

    // A pass that only reads the tiles: visit(const PreparedTile&).
    template <class Visit>
    void read(const ProgressSpan& progress, Visit&& visit) {
        each(progress, true, [&](PreparedTile& t) { visit(static_cast<const PreparedTile&>(t)); });
    }
    // The last pass: visit(PreparedTile&) may overwrite the tile, e.g. with its reconstruction.
    template <class Visit>
    void consume(const ProgressSpan& progress, Visit&& visit) {
        each(progress, false, visit);
    }
    // Adds the means back, undoes the transform and writes the tile's series to output.
    void finish(PreparedTile& t, Sequence& output) const;

private:
    template <class Visit>
    void each(const ProgressSpan& progress, bool keep, Visit&& visit) {
        if (cached_) {
            progress.report(0.0);
            visit(*cached_);
            if (!keep) cached_.reset();
            progress.report(1.0);
            return;
        }
        for (size_t i = 0; i < tiles_.size(); ++i) {
            progress.report(static_cast<double>(i) / tiles_.size());
            auto t = std::make_unique<PreparedTile>();
            prepare(tiles_[i], *t);
            visit(*t);
            if (keep && tiles_.size() == 1) cached_ = std::move(t);
        }
        progress.report(1.0);
    }
    void prepare(PixelRange range, PreparedTile& t) const;

    const Sequence& input_;
    ChannelSelection group_;
    SeriesPrep prep_;
    std::vector<PixelRange> tiles_;
    std::unique_ptr<PreparedTile> cached_;
};

}  // namespace statfilter
