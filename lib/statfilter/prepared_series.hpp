// The time series of one channel group, ready for temporal work: gathered tile by tile, repaired,
// cleared of fireflies (statfilter/temporal_outliers.hpp), transformed relative to the group's level
// and centred; on the way back each series keeps its linear-domain mean and, when it had no negative
// sample, stays non-negative (inverse_transform_keeping_mean). Filters make several passes (basis, then reconstruction); when the whole
// group fits in one tile of the memory budget it is prepared once and kept for every pass.
#pragma once
#include <memory>
#include <vector>

#include "statfilter/nonfinite.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/temporal_outliers.hpp"
#include "statfilter/time_series_tiles.hpp"
#include "statfilter/value_transform.hpp"

namespace statfilter {

// How a gathered tile becomes the centred series the basis describes.
struct SeriesPrep {
    ValueTransform transform = ValueTransform::None;
    bool repair_nonfinite = false;
    // The transform's scale: scale if > 0, else scale_factor x the group's level (transform_level),
    // measured once by PreparedSeries before any pass.
    double scale = 0;
    double scale_factor = 1;
    double outlier_z = 0;          // fireflies beyond this many robust deviations are replaced; 0 = off
    bool keep_mean = true;         // the inverse keeps each series' linear mean and sign (see above)
};

// Repairs and transforms a gathered F x n tile, then centres every series; its means go to means[n].
// The transform's scale is prep.scale (1 when not set).
void prepare_tile(double* tile, int64_t frames, int64_t n, const SeriesPrep& prep, double* means);

// One prepared tile: tile[f * n + j] is series j in frame f, centred; means[j] its mean.
// linear_means[j] and non_negative[j]: series j's mean and sign before the transform.
struct PreparedTile {
    PixelRange range;
    int64_t n = 0;
    std::vector<double> tile, means, linear_means;
    std::vector<uint8_t> non_negative;
};

class PreparedSeries {
public:
    // buffers_per_tile: how many F x n double buffers a pass holds at once (for the budget).
    // known: the fireflies already found (a later pass over a band of the shot: series indices of the
    // whole frame, the band's first series at first_series), else they are searched for here.
    PreparedSeries(const Sequence& input, ChannelSelection group, const SeriesPrep& prep, double budget_bytes,
                   int buffers_per_tile, const std::vector<TemporalOutlier>* known = nullptr, int64_t first_series = 0);

    int64_t frames() const { return input_.shape().frames; }
    const Shape& shape() const { return input_.shape(); }
    ChannelSelection group() const { return group_; }
    // The transform's scale in use, and the samples replaced as fireflies.
    double scale() const { return prep_.scale; }
    const std::vector<TemporalOutlier>& outliers() const { return outliers_; }

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
    // Passes prepare their tiles in `spare` (kept by the caller, which may lend it to the next
    // PreparedSeries) instead of buffers of their own; null: their own, freed after each pass.
    void lend_spare(PreparedTile* spare) { spare_ = spare; }
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
        // One tile's buffers for every tile of the pass (the caller's spare when it lent one): the
        // tiles are the same size but the last, and fresh ones would be page-faulted in anew.
        std::unique_ptr<PreparedTile> own;
        PreparedTile* t = spare_;
        if (!t) t = (own = std::make_unique<PreparedTile>()).get();
        for (size_t i = 0; i < tiles_.size(); ++i) {
            progress.report(static_cast<double>(i) / tiles_.size());
            prepare(tiles_[i], *t);
            visit(*t);
        }
        if (keep && tiles_.size() == 1) cached_ = own ? std::move(own) : std::make_unique<PreparedTile>(std::move(*t));
        progress.report(1.0);
    }
    void prepare(PixelRange range, PreparedTile& t) const;

    const Sequence& input_;
    ChannelSelection group_;
    SeriesPrep prep_;
    std::vector<PixelRange> tiles_;
    std::vector<TemporalOutlier> outliers_;
    std::unique_ptr<PreparedTile> cached_;
    PreparedTile* spare_ = nullptr;
};

}  // namespace statfilter
