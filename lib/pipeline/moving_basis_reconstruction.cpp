// The low-rank stage's second half for the moving basis: each group's operator M from the shot's
// Gram, then every band's series rebuilt as M x, the rows parked until the last band is done, then
// each frame handed on.
#include <algorithm>
#include <memory>

#include "pipeline/band_view.hpp"
#include "pipeline/low_rank_stage.hpp"
#include "pipeline/memory_budget.hpp"
#include "pipeline/moving_basis_operator.hpp"
#include "pipeline/parallel.hpp"
#include "pipeline/scratch_frames.hpp"

namespace statfilter {

void LowRankStage::reconstruct_moving(const FrameSource& source, LowRankStatistics stats, const FrameConsumer& consume,
                                      const StageContext& ctx, Results& results) const {
    const Shape& s = source.shape();
    const int64_t F = s.frames;
    const Progress none;
    const Progress& progress = ctx.progress ? *ctx.progress : none;
    const bool in_memory = source.in_memory() != nullptr;

    // Each group's operator, made once from its Gram (the plan's reduction of every tile's, or this run's).
    const RankRule rule = [this](const std::vector<double>& ev, int64_t series, int64_t frames) {
        return options_.rank(ev, series, frames).rank;
    };
    std::vector<MovingOperator> operators;
    double rank_sum = 0;
    int64_t windows = 0;
    for (LowRankStatistics::Group& g : stats.groups) {
        operators.push_back(moving_basis_operator(g.gram, F, g.series, options_.moving, rule));
        rank_sum += operators.back().rank_sum;
        windows += operators.back().windows;
        std::vector<double>().swap(g.gram);
        g.basis.reset();
    }

    // Pass 2's bands: the kept band, or as many rows as the budget leaves beside the operators.
    bool keep = stats.keep;
    int64_t rows = stats.rows;
    if (!in_memory) {
        check_memory_budget(held_bytes(s, 0, ctx.threads, 1), ctx.budget_bytes, "the moving basis");
        if (keep && held_bytes(s, 0, ctx.threads, rows) > ctx.budget_bytes) {
            keep = stats.keep = false;
            stats.kept_band.reset();
        }
        if (!keep) {
            for (auto& c : stats.cached) c.reset();
            std::vector<float>().swap(stats.buffer);
            const auto fit = static_cast<int64_t>((ctx.budget_bytes - pass_bytes(s, 0)) / band_row_bytes(s));
            rows = std::max<int64_t>(1, std::min(rows, fit));
        }
    }
    const int64_t bands = keep ? 1 : (s.height + rows - 1) / rows;

    // The rebuilt rows wait for the last band: in memory when one band is the shot, else on disk.
    std::unique_ptr<Sequence> whole;
    std::unique_ptr<ScratchFrames> parked;
    if (bands > 1) parked = std::make_unique<ScratchFrames>(s, source.attributes());
    std::vector<double> scratch;
    for (int64_t b = 0; b < bands; ++b) {
        const int64_t y0 = keep ? 0 : b * rows, y1 = keep ? s.height : std::min(s.height, y0 + rows);
        const double at = 0.4 + 0.45 * b / bands, span = 0.45 / bands;
        auto band = keep ? std::move(stats.kept_band)
                         : band_view(source, y0, y1, stats.buffer, ctx.threads, {progress, at, 0, "read"});
        auto out = std::make_unique<Sequence>(Shape{F, y1 - y0, s.width, s.channels});
        for (size_t g = 0; g < operators.size(); ++g) {
            PreparedSeries& series = stats.series(g, *band, y0);
            series.consume({progress, at + span * g / operators.size(), span / operators.size(), "reconstruct"},
                           [&](PreparedTile& t) {
                               apply_moving_operator(operators[g], F, t.n, t.tile, scratch);
                               series.finish(t, *out);
                           });
        }
        for (auto& c : stats.cached) c.reset();
        if (!parked) {
            whole = std::move(out);
            continue;
        }
        parallel_for(F, ctx.threads, [&](int64_t f) { parked->write_rows(f, y0, y1, &out->at(f, 0, 0, 0)); },
                     {progress, at + span, 0, "park"});
    }
    stats.spare_tile.reset();
    std::vector<float>().swap(stats.buffer);
    std::vector<double>().swap(scratch);

    // Each frame handed on: from memory, or read back whole from the parked rows.
    std::vector<std::vector<float>> frames(static_cast<size_t>(parked ? worker_count(F, ctx.threads) : 0));
    parallel_for_workers(F, ctx.threads, [&](int64_t t, int worker) {
        if (!parked) return consume(t, &whole->at(t, 0, 0, 0));
        std::vector<float>& frame = frames[static_cast<size_t>(worker)];
        frame.resize(static_cast<size_t>(s.pixels() * s.channels));
        parked->read_rows(t, 0, s.height, frame.data());
        consume(t, frame.data());
    }, {progress, 0.85, 0.15, "reconstruct"});

    results.set("bands", static_cast<double>(stats.bands));
    results.set("mean_rank", windows > 0 ? rank_sum / static_cast<double>(windows) : 0.0);
    results.set("nonfinite_repaired", static_cast<double>(stats.repaired));
}

}  // namespace statfilter
