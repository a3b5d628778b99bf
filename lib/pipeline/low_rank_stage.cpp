#include "pipeline/low_rank_stage.hpp"

#include <cblas.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "filters/low_rank_reconstruction.hpp"
#include "filters/temporal_params.hpp"
#include "pipeline/band_view.hpp"
#include "pipeline/memory_budget.hpp"
#include "pipeline/parallel.hpp"
#include "statfilter/box_mean.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

// One channel group's model: its Gram, basis and rank, then every series' mean and coefficients.
struct GroupModel {
    ChannelSelection group;
    std::vector<double> gram;
    int64_t series = 0;
    TemporalBasis basis;
    RankChoice choice;
    int64_t stored = 0;           // components kept per series (the rank, or max_rank per pixel)
    std::vector<float> coeff;     // stored x n_total, component-major; series j = pixel * count + channel
                                  // (float: the frames rebuilt from them are float; half the memory)
    std::vector<double> means;    // n_total
    SeriesPrep prep;              // the options' preparation with this group's transform scale fixed
    std::vector<double> linear_means;         // keep_mean: each series' mean before the transform ...
    std::vector<uint8_t> non_negative;        // ... and whether it had no negative sample
    std::vector<MeanCorrection> corrections;  // ... giving each series' correction on the way back
    std::vector<int64_t> ranks;   // per pixel (error threshold)
    std::vector<cv::Mat> planes;  // error threshold: pooled coefficient energy per component, and beyond
    cv::Mat tail;
};

// The same mean whatever the threads or the band around the rows (statfilter/box_mean.hpp).
void pool(cv::Mat& plane, int window, int threads) {
    box_mean(plane.ptr<double>(), plane.rows, plane.cols, window, threads);
}

// Error threshold: per-pixel ranks from the pooled coefficient energies (the study's Delta(error)
// test against the local noise energy, estimated from the components beyond max_rank).
void choose_pixel_ranks(GroupModel& m, const LowRankOptions& o, const Shape& s, int threads) {
    for (auto& plane : m.planes) pool(plane, o.window, threads);
    pool(m.tail, o.window, threads);
    const int64_t useful = max_useful_rank(m.basis.series, m.basis.frames);
    const int64_t tail_components = useful - m.stored;
    // Without a tail (max_rank leaves none, few frames) the global noise estimate stands in.
    const double global_noise =
        std::pow(gavish_donoho_rank(m.basis.eigenvalues, m.basis.series, m.basis.frames).noise_sigma, 2) * m.group.count;
    m.ranks.assign(static_cast<size_t>(s.pixels()), 0);
    for (int64_t p = 0; p < s.pixels(); ++p) {
        const double noise = tail_components > 0 ? m.tail.at<double>(static_cast<int>(p)) / tail_components : global_noise;
        int64_t k = 0;
        while (k < m.stored && m.planes[k].at<double>(static_cast<int>(p)) > o.threshold * noise) ++k;
        m.ranks[static_cast<size_t>(p)] = k;
    }
}

}  // namespace

Footprint LowRankStage::footprint() const {
    Footprint f;
    f.reach = TemporalReach::Shot;
    f.halo = options_.per_pixel ? options_.window / 2 : 0;  // pooling reads the coefficient images, not the input
    f.passes = 2;
    f.streams = true;
    return f;
}

double LowRankStage::band_row_bytes(const Shape& s) const {
    // The band in float plus its prepared double tile (PreparedSeries keeps one tile at a time); the
    // moving basis also its rebuilt rows, in float.
    const double samples = static_cast<double>(s.frames) * s.width * s.channels;
    return samples * (sizeof(float) + sizeof(double) + (moving() ? sizeof(float) : 0));
}

double LowRankStage::pass_bytes(const Shape& s, int64_t rank) const {
    const auto groups = static_cast<double>(basis_groups(s, options_.shared_basis).size());
    // The moving basis holds no coefficients: each group's Gram, the copy its windows read, its
    // operator and the plan's basis.
    if (moving()) return groups * 4.0 * s.frames * s.frames * sizeof(double);
    const double P = static_cast<double>(s.pixels()), C = static_cast<double>(s.channels);
    const double stored = options_.per_pixel ? std::min<int64_t>(options_.max_rank, s.frames - 1) : rank;
    double bytes = stored * P * C * sizeof(float) + P * C * sizeof(double);  // coefficients and means
    if (options_.prep.keep_mean) bytes += P * C * (sizeof(double) + 1);      // linear means and signs
    // Each channel group's energies (stored + 1 planes) and ranks, all held at once; and the row sums
    // box_mean pools one plane at a time through.
    if (options_.per_pixel) bytes += groups * ((stored + 1) * P * sizeof(double) + P * sizeof(int64_t)) + P * sizeof(double);
    bytes += groups * 2.0 * s.frames * s.frames * sizeof(double);            // Gram and basis
    return bytes;
}

double LowRankStage::emission_bytes(const Shape& s, int64_t rank, int threads) const {
    const double P = static_cast<double>(s.pixels()), C = static_cast<double>(s.channels);
    if (moving()) return pass_bytes(s, 0) + threads * P * C * sizeof(float);  // a frame read back per thread
    const double stored = options_.per_pixel ? std::min<int64_t>(options_.max_rank, s.frames - 1) : rank;
    double bytes = stored * P * C * sizeof(float) + P * C * sizeof(double);
    // The corrections are solved while the linear means are still held.
    if (options_.prep.keep_mean) bytes += P * C * (sizeof(double) + 1 + sizeof(MeanCorrection));
    const auto groups = static_cast<double>(basis_groups(s, options_.shared_basis).size());
    if (options_.per_pixel) bytes += groups * P * sizeof(int64_t) + P * sizeof(float);
    const double chunk = std::min<double>(kRebuildChunk, P * C);
    bytes += threads * (P * C * sizeof(float) + chunk * sizeof(double));  // a frame being rebuilt per thread
    bytes += groups * 2.0 * s.frames * s.frames * sizeof(double);
    return bytes;
}

double LowRankStage::held_bytes(const Shape& s, int64_t rank, int threads, int64_t band_rows) const {
    return std::max(pass_bytes(s, rank) + band_rows * band_row_bytes(s), emission_bytes(s, rank, threads));
}

double LowRankStage::min_bytes(const Shape& s, int threads) const {
    const int64_t rank = options_.per_pixel ? options_.max_rank : moving() ? 0 : options_.known_rank;
    return held_bytes(s, std::min<int64_t>(rank, std::max<int64_t>(s.frames - 1, 0)), threads, 1);
}

void LowRankStage::run(const FrameSource& source, const FrameConsumer& consume, const StageContext& ctx, Results& results) {
    reconstruct(source, statistics(source, ctx), consume, ctx, results);
}

LowRankStatistics LowRankStage::statistics(const FrameSource& source, const StageContext& ctx, const BandVisitor& also) const {
    const Shape& s = source.shape();
    const int64_t F = s.frames;
    const Progress none;
    const Progress& progress = ctx.progress ? *ctx.progress : none;
    LowRankStatistics stats;
    std::vector<LowRankStatistics::Group>& models = stats.groups;
    for (const ChannelSelection& g : basis_groups(s, options_.shared_basis)) {
        LowRankStatistics::Group m;
        m.group = g;
        m.gram.assign(static_cast<size_t>(F * F), 0.0);
        models.push_back(std::move(m));
    }
    // The transform's scale of each group, measured once before the passes (or carried by a plan),
    // so every band and tile sees the same transform.
    const std::vector<double> scales = options_.scales.empty() ? transform_scales(source) : options_.scales;
    if (scales.size() != models.size())
        throw Error(Status::InvalidArgument, "the plan carries " + std::to_string(scales.size()) +
                                                 " transform scales but the shot has " + std::to_string(models.size()) +
                                                 " channel groups");
    for (size_t g = 0; g < models.size(); ++g) {
        models[g].prep = options_.prep;
        if (scales[g] > 0) models[g].prep.scale = scales[g];
    }

    // Band height: the whole shot when it is in memory, else as many rows as the budget leaves. A
    // single band (the shot fits) is kept, with its prepared tiles, for the second pass: one read.
    const bool in_memory = source.in_memory() != nullptr;
    const int64_t bound_rank = options_.per_pixel ? options_.max_rank : moving() ? 0 : options_.known_rank;
    const double fixed = pass_bytes(s, std::min<int64_t>(bound_rank, std::max<int64_t>(F - 1, 0)));
    const auto fit_rows = static_cast<int64_t>((ctx.budget_bytes - fixed) / band_row_bytes(s));
    const int64_t rows = in_memory ? s.height : std::max<int64_t>(1, std::min(s.height, fit_rows));
    bool keep = rows >= s.height;
    // The band's prepared tiles and the firefly search's tiles (one per thread) share the band's
    // double allowance: half each.
    stats.tile_budget = in_memory ? ctx.budget_bytes : 0.5 * rows * s.frames * s.width * s.channels * sizeof(double);
    stats.rows = rows;
    stats.keep = keep;
    stats.cached.resize(models.size());
    stats.fireflies.resize(models.size());
    const int64_t bands = (s.height + rows - 1) / rows;
    stats.bands = bands;

    // Pass 1: the Gram of every group, band by band.
    for (int64_t b = 0; b < bands; ++b) {
        const int64_t y0 = b * rows, y1 = std::min(s.height, y0 + rows);
        const double at = 0.4 * b / bands, span = 0.4 / bands;
        auto band = band_view(source, y0, y1, stats.buffer, ctx.threads, {progress, at, 0.5 * span, "read"});
        stats.repaired += check_nonfinite(*band, options_.nonfinite, y0);
        if (also) also(*band, y0);
        for (size_t g = 0; g < models.size(); ++g) {
            LowRankStatistics::Group& m = models[g];
            stats.series(g, *band, y0).read({progress, at + span * (0.5 + 0.5 * g / models.size()), 0.5 * span / models.size(), "basis"},
                                        [&](const PreparedTile& t) {
                                            if (options_.gram) accumulate_gram(t, F, m.gram);
                                            m.series += t.n;
                                        });
        }
        if (keep) stats.kept_band = std::move(band);
    }
    stats.fireflies_known = true;
    return stats;
}

std::vector<double> LowRankStage::transform_scales(const FrameSource& source) const {
    const Shape& s = source.shape();
    std::vector<double> scales;
    // Read here when the shot is not in memory: the frames transform_level_frames picks.
    std::unique_ptr<Sequence> level_frames;
    for (const ChannelSelection& g : basis_groups(s, options_.shared_basis)) {
        SeriesPrep prep = options_.prep;
        if (prep.scale > 0 || prep.transform == ValueTransform::None) {
            scales.push_back(prep.scale);
            continue;
        }
        const Sequence* probe = source.in_memory();
        if (!probe) {
            if (!level_frames) {
                const std::vector<int64_t> picked = transform_level_frames(s.frames);
                const Shape ps{static_cast<int64_t>(picked.size()), s.height, s.width, s.channels};
                level_frames = std::make_unique<Sequence>(ps);
                for (size_t i = 0; i < picked.size(); ++i)
                    source.read_rows(picked[i], 0, s.height, &level_frames->at(static_cast<int64_t>(i), 0, 0, 0));
            }
            probe = level_frames.get();
        }
        double scale = prep.scale_factor * transform_level(*probe, g);
        if (!(scale > 0) || !std::isfinite(scale)) scale = 1.0;
        scales.push_back(scale);
    }
    return scales;
}

PreparedSeries& LowRankStatistics::series(size_t g, const Sequence& band, int64_t y0) {
    if (cached[g] && keep) return *cached[g];
    const int64_t first = y0 * band.shape().width * groups[g].group.count;
    cached[g] = std::make_unique<PreparedSeries>(band, groups[g].group, groups[g].prep, tile_budget, 3,
                                                 fireflies_known ? &fireflies[g] : nullptr, first);
    cached[g]->lend_spare(spare_tile.get());
    if (!fireflies_known)
        for (TemporalOutlier o : cached[g]->outliers()) {
            o.series += first;
            fireflies[g].push_back(o);
        }
    return *cached[g];
}

void LowRankStage::reconstruct(const FrameSource& source, LowRankStatistics stats, const FrameConsumer& consume,
                               const StageContext& ctx, Results& results) const {
    if (moving()) return reconstruct_moving(source, std::move(stats), consume, ctx, results);
    const Shape& s = source.shape();
    const int64_t F = s.frames;
    const Progress none;
    const Progress& progress = ctx.progress ? *ctx.progress : none;
    const bool in_memory = source.in_memory() != nullptr;
    const int64_t rows = stats.rows, bands = stats.bands;
    bool keep = stats.keep;
    std::vector<float>& buffer = stats.buffer;
    std::unique_ptr<Sequence>& kept_band = stats.kept_band;
    std::vector<std::unique_ptr<PreparedSeries>>& cached = stats.cached;
    const int64_t repaired = stats.repaired;
    auto series_of = [&](size_t g, const Sequence& band, int64_t y0) -> PreparedSeries& { return stats.series(g, band, y0); };
    std::vector<GroupModel> models;
    for (LowRankStatistics::Group& g : stats.groups) {
        GroupModel m;
        m.group = g.group;
        m.gram = std::move(g.gram);
        m.series = g.series;
        m.prep = g.prep;
        if (g.basis) m.basis = *g.basis;
        models.push_back(std::move(m));
    }
    for (GroupModel& m : models) {
        if (m.basis.frames == 0) m.basis = basis_from_gram(std::move(m.gram), F, m.series);
        if (options_.per_pixel) {
            m.stored = std::min(options_.max_rank, max_useful_rank(m.basis.series, m.basis.frames));
            for (int64_t i = 0; i < m.stored; ++i)
                m.planes.emplace_back(static_cast<int>(s.height), static_cast<int>(s.width), CV_64F, cv::Scalar(0));
            m.tail = cv::Mat(static_cast<int>(s.height), static_cast<int>(s.width), CV_64F, cv::Scalar(0));
        } else {
            m.choice = options_.rank(m.basis.eigenvalues, m.basis.series, m.basis.frames);
            m.stored = m.choice.rank;
        }
    }

    // The coefficients' size is known now (an automatic rank): the bands of pass 2 shrink to leave
    // room for them (the kept band is let go if it must be), or the run stops here, before anything
    // is written. Pass 1's band buffer (and spare tile), sized for its taller bands, go before the
    // coefficients come: their pages would otherwise stay resident beside them.
    int64_t rows2 = rows;
    if (!in_memory) {
        int64_t most = 0;
        for (const GroupModel& m : models) most = std::max(most, m.stored);
        const double held = pass_bytes(s, most);
        if (keep && held_bytes(s, most, ctx.threads, rows) > ctx.budget_bytes) {
            keep = stats.keep = false;
            kept_band.reset();
            for (auto& c : cached) c.reset();
        }
        check_memory_budget(held_bytes(s, most, ctx.threads, 1), ctx.budget_bytes,
                            "the temporal model (" + std::to_string(most) + " components per series)");
        if (!keep) {
            rows2 = std::max<int64_t>(1, std::min(rows, static_cast<int64_t>((ctx.budget_bytes - held) / band_row_bytes(s))));
            for (auto& c : cached) c.reset();  // pass 1's last band and the tiles it kept
            std::vector<float>().swap(buffer);
            if (rows2 < rows) stats.spare_tile = std::make_unique<PreparedTile>();  // sized for pass 1's bands too
        }
    }
    for (GroupModel& m : models) {
        const auto n_total = static_cast<size_t>(s.pixels() * m.group.count);
        m.coeff.assign(static_cast<size_t>(m.stored) * n_total, 0.0f);
        m.means.assign(n_total, 0.0);
        if (m.prep.keep_mean) {
            m.linear_means.assign(n_total, 0.0);
            m.non_negative.assign(n_total, 1);
        }
    }
    const int64_t bands2 = keep ? 1 : (s.height + rows2 - 1) / rows2;

    // Pass 2: every series' mean and coefficients (and, per pixel, their energies).
    std::vector<double> a;
    for (int64_t b = 0; b < bands2; ++b) {
        const int64_t y0 = b * rows2, y1 = std::min(s.height, y0 + rows2);
        const double at = 0.4 + 0.3 * b / bands2, span = 0.3 / bands2;
        auto band = keep ? std::move(kept_band) : band_view(source, y0, y1, buffer, ctx.threads, {progress, at, 0, "read"});
        for (size_t g = 0; g < models.size(); ++g) {
            GroupModel& m = models[g];
            const int64_t count = m.group.count, K = m.stored;
            const auto n_total = static_cast<int64_t>(m.means.size());
            const int64_t offset = y0 * s.width * count;  // the band's first series in the whole frame
            auto keep = [&](const PreparedTile& t) {
                const int64_t n = t.n, first = offset + t.range.begin * count;
                a.resize(static_cast<size_t>(std::max<int64_t>(K, 1) * n));
                if (K > 0) project_onto_basis(m.basis, K, t.tile.data(), n, a.data());
                std::copy(t.means.begin(), t.means.end(), m.means.begin() + first);
                if (m.prep.keep_mean) {
                    std::copy(t.linear_means.begin(), t.linear_means.end(), m.linear_means.begin() + first);
                    std::copy(t.non_negative.begin(), t.non_negative.end(), m.non_negative.begin() + first);
                }
                for (int64_t i = 0; i < K; ++i)
                    for (int64_t j = 0; j < n; ++j) m.coeff[static_cast<size_t>(i * n_total + first + j)] = static_cast<float>(a[i * n + j]);
                if (!options_.per_pixel) return;
                for (int64_t j = 0; j < n; ++j) {
                    const auto p = static_cast<int>(y0 * s.width + t.range.begin + j / count);
                    double total = 0, kept = 0;
                    for (int64_t f = 0; f < F; ++f) total += t.tile[f * n + j] * t.tile[f * n + j];
                    for (int64_t i = 0; i < K; ++i) {
                        const double ai2 = a[i * n + j] * a[i * n + j];
                        m.planes[i].at<double>(p) += ai2;
                        kept += ai2;
                    }
                    m.tail.at<double>(p) += std::max(0.0, total - kept);
                }
            };
            series_of(g, *band, y0).consume({progress, at + span * g / models.size(), span / models.size(), "coefficients"}, keep);
        }
        for (auto& c : cached) c.reset();
    }
    stats.spare_tile.reset();
    if (options_.per_pixel)
        for (GroupModel& m : models) {
            choose_pixel_ranks(m, options_, s, ctx.threads);
            m.planes.clear();
            m.tail.release();
        }

    // keep_mean: each series' correction on the way back, solved once from its whole rebuilt series
    // (the frames are then rebuilt one at a time and each corrected with it).
    const int64_t P = s.pixels();
    for (GroupModel& m : models) {
        if (!m.prep.keep_mean) continue;
        const int64_t count = m.group.count, n_total = static_cast<int64_t>(m.means.size());
        m.corrections.assign(static_cast<size_t>(n_total), MeanCorrection());
        const int64_t chunk = 4096;
        parallel_for((n_total + chunk - 1) / chunk, ctx.threads, [&](int64_t c) {
            std::vector<double> x(static_cast<size_t>(F));
            for (int64_t j = c * chunk; j < std::min(n_total, (c + 1) * chunk); ++j) {
                const int64_t rank = m.ranks.empty() ? m.stored : m.ranks[static_cast<size_t>(j / count)];
                for (int64_t f = 0; f < F; ++f) {
                    double v = 0;
                    for (int64_t i = 0; i < rank; ++i) v += m.basis.vector(f, i) * m.coeff[i * n_total + j];
                    x[f] = v + m.means[j];
                }
                inverse_transform(m.prep.transform, m.prep.scale, x.data(), x.size());
                m.corrections[j] = solve_mean_correction(m.prep.transform, m.prep.scale, x.data(), F, m.linear_means[j],
                                                         m.non_negative[j] != 0);
            }
        }, {progress, 0.7, 0.0, "reconstruct"});
        m.linear_means.clear();
        m.non_negative.clear();
    }

    // Each frame rebuilt on its own, x_t = mu + sum_i V[t, i] a_i, undone from the transform.
    // A worker's frame is made once (every channel of it is rewritten for each frame).
    struct RebuildBuffers {
        std::vector<float> frame;
        std::vector<double> values;
    };
    std::vector<RebuildBuffers> rebuild_buffers(static_cast<size_t>(worker_count(F, ctx.threads)));
    parallel_for_workers(F, ctx.threads, [&](int64_t t, int worker) {
        std::vector<float>& frame = rebuild_buffers[static_cast<size_t>(worker)].frame;
        std::vector<double>& values = rebuild_buffers[static_cast<size_t>(worker)].values;
        frame.resize(static_cast<size_t>(P * s.channels));
        constexpr double lim = std::numeric_limits<float>::max();
        for (const GroupModel& m : models) {
            const int64_t count = m.group.count, n_total = static_cast<int64_t>(m.means.size());
            // In chunks of series: each is rebuilt on its own, so a chunk needs only its own doubles.
            for (int64_t j0 = 0; j0 < n_total; j0 += kRebuildChunk) {
                const int64_t n = std::min(kRebuildChunk, n_total - j0);
                values.assign(static_cast<size_t>(n), 0.0);
                for (int64_t i = 0; i < m.stored; ++i) {
                    const double v = m.basis.vector(t, i);
                    const float* ai = m.coeff.data() + i * n_total + j0;
                    if (m.ranks.empty()) {
                        for (int64_t j = 0; j < n; ++j) values[j] += v * ai[j];
                    } else {
                        for (int64_t j = 0; j < n; ++j)
                            if (i < m.ranks[static_cast<size_t>((j0 + j) / count)]) values[j] += v * ai[j];
                    }
                }
                for (int64_t j = 0; j < n; ++j) values[j] += m.means[j0 + j];
                inverse_transform(m.prep.transform, m.prep.scale, values.data(), values.size());
                if (!m.corrections.empty())
                    for (int64_t j = 0; j < n; ++j) values[j] = m.corrections[j0 + j].apply(values[j]);
                for (int64_t j = 0; j < n; ++j) {
                    const double x = values[j];  // saturate at the float range; NaN passes through
                    const int64_t series = j0 + j;
                    frame[static_cast<size_t>((series / count) * s.channels + m.group.first + series % count)] =
                        static_cast<float>(x > lim ? lim : (x < -lim ? -lim : x));
                }
            }
        }
        consume(t, frame.data());
    }, {progress, 0.7, 0.3, "reconstruct"});

    results.set("bands", static_cast<double>(bands));  // bands of scanlines of the statistics pass
    if (options_.per_pixel) {
        auto rank_map = std::make_shared<Sequence>(Shape{1, s.height, s.width, static_cast<int64_t>(models.size())});
        double rank_sum = 0;
        for (size_t g = 0; g < models.size(); ++g) {
            for (int64_t p = 0; p < P; ++p) {
                const auto k = models[g].ranks[static_cast<size_t>(p)];
                rank_sum += static_cast<double>(k);
                rank_map->at(0, p / s.width, p % s.width, static_cast<int64_t>(g)) = static_cast<float>(k);
            }
            rank_map->channel_names()[g] =
                models.size() == 1 ? "rank" : "rank." + source.attributes().channel_names()[models[g].group.first];
        }
        results.set("mean_rank", rank_sum / (static_cast<double>(P) * models.size()));
        results.set("nonfinite_repaired", static_cast<double>(repaired));
        results.set_image("rank_map", rank_map);
        return;
    }
    std::string ranks;
    double noise = 0;
    for (const GroupModel& m : models) {
        ranks += (ranks.empty() ? "" : ",") + std::to_string(m.choice.rank);
        noise = std::max(noise, m.choice.noise_sigma);
    }
    if (models.size() == 1) {
        results.set("rank", static_cast<double>(models.front().choice.rank));
    } else {
        results.set("rank", ranks);
    }
    if (options_.report_noise) results.set("noise_sigma", noise);
    results.set("nonfinite_repaired", static_cast<double>(repaired));
}

LowRankOptions low_rank_options(const ParamSet& params, LowRankModel model) {
    const TemporalSetup setup = temporal_setup(params);
    const bool per_pixel = model == LowRankModel::PerPixel;
    LowRankOptions o;
    o.prep = setup.prep;
    o.nonfinite = setup.nonfinite;
    o.shared_basis = setup.shared_basis;
    o.per_pixel = per_pixel;
    if (per_pixel) {
        o.max_rank = params.get_int("max_rank");
        o.threshold = params.get_float("threshold");
        o.window = static_cast<int>(params.get_int("window"));
    } else {
        const ParamSet rank_params = params;  // the rule keeps its own copy of the rank parameters
        o.rank = [rank_params](const std::vector<double>& ev, int64_t series, int64_t frames) {
            return choose_rank(rank_params, ev, series, frames);
        };
        o.report_noise = params.get_string("rank") == "auto";
        int64_t fixed = 0;
        if (params.get_integer_choice("rank", fixed)) o.known_rank = fixed;
    }
    if (model == LowRankModel::Moving) {
        o.moving.half_width = params.get_int("half_width");
        o.moving.sigma = params.get_float("sigma");
        o.moving.weights = parse_window_weights(params.get_string("weights"));
        o.report_noise = false;
    }
    return o;
}

}  // namespace statfilter
