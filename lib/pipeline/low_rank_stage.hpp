// Global temporal PCA (rank fixed, by energy or automatic), the study's error threshold method
// (per-pixel ranks) and the moving basis (a PCA of the frames around each frame), as a stage that
// streams: a statistics pass over bands of scanlines of every
// frame accumulates the F x F Gram; a second pass over the bands projects every series onto the
// basis and keeps its coefficients (K images) and mean; then each frame is rebuilt on its own,
// x_t = mu + sum_i V[t, i] a_i, and handed on as soon as it is final. Memory is the band (set by the
// budget) plus K + 1 coefficient images, never the shot. In memory the band is the whole shot and
// the passes read it in place. The moving basis shares the statistics pass (its operator is made
// from the same Gram); its second pass applies the operator band by band and parks the rebuilt rows
// (in memory when one band holds the shot, else in a scratch file) until every band is done.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "pipeline/moving_basis_operator.hpp"
#include "pipeline/stage.hpp"
#include "statfilter/nonfinite.hpp"
#include "statfilter/params.hpp"
#include "statfilter/prepared_series.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/temporal_basis.hpp"

namespace statfilter {

struct LowRankOptions {
    SeriesPrep prep;
    NonFinitePolicy nonfinite = NonFinitePolicy::Error;
    bool shared_basis = true;
    // Global rank: from the basis' eigenvalues, the series count and the frame count.
    std::function<RankChoice(const std::vector<double>&, int64_t, int64_t)> rank;
    bool report_noise = false;  // rank=auto: report the estimated noise sigma
    int64_t known_rank = 1;     // the rank when it is fixed; else 1, the least (memory is checked again once known)
    // Per-pixel ranks (the error threshold method) instead of one global rank.
    bool per_pixel = false;
    int64_t max_rank = 8;
    double threshold = 2;
    int window = 9;
    // The moving basis instead of one basis (half_width > 0); its windows' ranks by `rank`.
    MovingWindow moving;
    // Each channel group's transform scale, measured once on the whole shot by a plan of tile tasks
    // (transform_scales); empty = measured by the statistics pass on its own source.
    std::vector<double> scales;
    // false: the statistics pass finds the fireflies and keeps the band but sums no Gram (a tile
    // task that is handed the reduction of every tile's Gram).
    bool gram = true;
};

// What the statistics pass found: each channel group's transform scale, Gram and series count, and
// how the shot was cut into bands. When the shot fits in one band, the band (and its prepared tiles)
// is kept here for the passes that follow: the shot is read once.
struct LowRankStatistics {
    struct Group {
        ChannelSelection group;
        SeriesPrep prep;  // the options' preparation with this group's transform scale fixed
        std::vector<double> gram;
        int64_t series = 0;
        // The basis already made from the gram (a plan's reduction of every tile's Gram); null =
        // made by reconstruct.
        std::shared_ptr<const TemporalBasis> basis;
    };
    std::vector<Group> groups;
    int64_t rows = 0, bands = 0;  // band height and count of the statistics pass
    bool keep = false;            // one band, kept
    double tile_budget = 0;       // bytes a band's prepared tiles may take
    int64_t repaired = 0;         // non-finite samples repaired
    std::vector<float> buffer;    // the band read (when the source does not hold the shot)
    std::unique_ptr<Sequence> kept_band;
    std::vector<std::unique_ptr<PreparedSeries>> cached;
    // The tile buffers every group's passes prepare their tiles in (one tile at a time); let go
    // before the frames are rebuilt.
    std::unique_ptr<PreparedTile> spare_tile = std::make_unique<PreparedTile>();
    // Each group's fireflies as the statistics pass found them (series indices of the whole frame):
    // every later pass replaces the same samples, whatever its bands.
    std::vector<std::vector<TemporalOutlier>> fireflies;
    bool fireflies_known = false;
    // Group g's prepared series over rows [y0, ...) of every frame: the kept one, or made for this band.
    PreparedSeries& series(size_t g, const Sequence& band, int64_t y0);
};

// Sees every band of the statistics pass (rows [y0, y0 + band.height) of every frame), so another
// statistic can be gathered in the same read.
using BandVisitor = std::function<void(const Sequence& band, int64_t y0)>;

class LowRankStage final : public StreamStage {
public:
    explicit LowRankStage(LowRankOptions options) : options_(std::move(options)) {}

    Footprint footprint() const override;
    double min_bytes(const Shape& shape, int threads) const override;
    // Runs the passes over the source and hands every rebuilt frame to consume. Results: rank (or
    // mean_rank and the image rank_map), noise_sigma, nonfinite_repaired.
    void run(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
             Results& results) override;

    // The two halves of run, for a stage that gathers more statistics in between (the hybrid's
    // motion analysis shares the Gram): the statistics pass, then the reconstruction from it.
    LowRankStatistics statistics(const FrameSource& source, const StageContext& context, const BandVisitor& also = {}) const;
    void reconstruct(const FrameSource& source, LowRankStatistics statistics, const FrameConsumer& consume,
                     const StageContext& context, Results& results) const;
    const LowRankOptions& options() const { return options_; }
    // Each channel group's transform scale as the statistics pass measures it on this source (on
    // the frames transform_level_frames picks); 0 where the transform needs none.
    std::vector<double> transform_scales(const FrameSource& source) const;

    // Bytes held besides the band while the passes read the shot, with `rank` components per series;
    // bytes held while the frames are rebuilt (no band then); the larger of the two with a band of
    // band_rows scanlines.
    double pass_bytes(const Shape& shape, int64_t rank) const;
    double emission_bytes(const Shape& shape, int64_t rank, int threads) const;
    double held_bytes(const Shape& shape, int64_t rank, int threads, int64_t band_rows) const;
    // Series rebuilt at a time per thread.
    static constexpr int64_t kRebuildChunk = 1 << 16;
    // Bytes per scanline of band.
    double band_row_bytes(const Shape& shape) const;

private:
    bool moving() const { return options_.moving.half_width > 0; }
    // reconstruct, for the moving basis (pipeline/moving_basis_reconstruction.cpp).
    void reconstruct_moving(const FrameSource& source, LowRankStatistics statistics, const FrameConsumer& consume,
                            const StageContext& context, Results& results) const;

    LowRankOptions options_;
};

// Which model the stage makes: one basis with a global rank (pca), per-pixel ranks
// (error-threshold), or a basis per window of frames (moving-basis).
enum class LowRankModel { Global, PerPixel, Moving };

// The typed options of the pca, error-threshold and moving-basis filters, from their parameter tables.
LowRankOptions low_rank_options(const ParamSet& params, LowRankModel model);

}  // namespace statfilter
