#include "filters/hybrid_stage.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <opencv2/imgproc.hpp>

#include "filters/builtin_filters.hpp"
#include "filters/frame_stages.hpp"
#include "filters/hybrid_analysis_file.hpp"
#include "filters/motion_analysis.hpp"
#include "filters/own_first_pass.hpp"
#include "filters/temporal_params.hpp"
#include "pipeline/band_view.hpp"
#include "pipeline/frame_stage_pool.hpp"
#include "pipeline/parallel.hpp"
#include "pipeline/scratch_frames.hpp"
#include "pipeline/workspace_pool.hpp"
#include "statfilter/aligned_frame.hpp"
#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/filter_registry.hpp"

namespace statfilter {
namespace {

// The temporal parameters the hybrid hands to the filters it is made of.
constexpr const char* kShared[] = {"transform", "transform_scale", "firefly_z", "keep_mean", "nonfinite", "shared_basis",
                                   "memory_mb"};

// A progress callback reporting [0, 1] into [start, start + span] of `outer`.
Progress part_of(const Progress& outer, double start, double span) {
    return Progress([&outer, start, span](double fraction, const char* stage) {
        outer.report(start + span * fraction, stage);
        return true;
    });
}

// A window frame: its samples, guide and flow image (aligned_frame.hpp).
struct WindowFrame {
    std::vector<float> values, guide;
    std::vector<uint8_t> image;
    std::vector<float> vectors;  // the renderer's, X Y Z W a pixel (when given)
};

// Frame f's flow image from the renderer's albedo/normal passes (make_pass_guide's frame, unscaled).
void surfaces_image(const GuideSources& passes, int64_t f, const Shape& s, std::vector<float>& rows,
                    std::vector<float>& guide, uint8_t* image) {
    const int64_t P = s.pixels();
    const int64_t groups = (passes.albedo ? 1 : 0) + (passes.normal ? 1 : 0);
    guide.resize(static_cast<size_t>(P * 3 * groups));
    int64_t group = 0;
    for (const FrameSource* pass : {passes.albedo, passes.normal}) {
        if (!pass) continue;
        const int64_t C = pass->shape().channels;
        rows.resize(static_cast<size_t>(P * C));
        pass->read_rows(f, 0, s.height, rows.data());
        pass_guide_pixels(rows.data(), C, pass == passes.normal, P, guide.data() + 3 * group, 3 * groups);
        ++group;
    }
    flow_image(guide.data(), s.width, s.height, 3 * groups, 1.0, image);
}

// Frame f's vectors, the first four channels of the pass, pixel-major.
void frame_vectors(const FrameSource& vectors, int64_t f, const Shape& s, std::vector<float>& rows, std::vector<float>& out) {
    const int64_t P = s.pixels(), C = vectors.shape().channels;
    out.resize(static_cast<size_t>(P * 4));
    if (C == 4) return vectors.read_rows(f, 0, s.height, out.data());
    rows.resize(static_cast<size_t>(P * C));
    vectors.read_rows(f, 0, s.height, rows.data());
    for (int64_t p = 0; p < P; ++p)
        for (int64_t c = 0; c < 4; ++c) out[static_cast<size_t>(p * 4 + c)] = rows[static_cast<size_t>(p * C + c)];
}

// As many threads as `bytes(threads)` fits in the budget, one at least.
int fitting_threads(const StageContext& ctx, const std::function<double(int)>& bytes) {
    int t = std::max(1, ctx.threads);
    while (t > 1 && bytes(t) > ctx.budget_bytes) --t;
    return t;
}

// Frame f of the input with the fireflies the statistics pass found replaced as the temporal model saw them.
void read_input(const FrameSource& source, const HybridAnalysis& analysis, int64_t f, float* frame) {
    source.read_rows(f, 0, source.shape().height, frame);
    if (!analysis.fireflies.empty())
        for (const auto& [i, v] : analysis.fireflies[static_cast<size_t>(f)]) frame[i] = v;
}

int64_t count_moving(const HybridAnalysis& analysis) {
    return static_cast<int64_t>(std::count_if(analysis.grown.begin(), analysis.grown.end(), [](float g) { return g > 0.0f; }));
}

double gain_of(const HybridAnalysis& analysis, int64_t f) {
    return analysis.frame_gain.empty() ? 1.0 : analysis.frame_gain[static_cast<size_t>(f)];
}

// A frame's buffers while its first pass is made (first_pass_bytes), kept from frame to frame where
// the budget holds them.
struct FirstPassScratch {
    std::vector<float> model, estimate, own;
    DiffusionWorkspace diffusion;
};

// Each frame's first pass from its I_T: I_T with the light diffusion pass; the frame's own diffusion
// where I_T ghosts (the flow then follows the object, and a pixel with nothing to average is no
// worse than a single-frame filter); its sums into the analysis. Frames come from any thread, each once.
class FirstPasses {
public:
    FirstPasses(const FrameSource& source, HybridAnalysis& analysis, const HybridStageOptions& options,
                const ParamSet& refine, bool keep)
        : source_(source), analysis_(analysis), moving_(moving_mask(analysis)),
          own_first_(source.shape(), analysis.crossings, analysis.change.get(), moving_, options.mc.half_width,
                     options.single_frame),
          refine_("postfilter", refine) {
        const auto F = static_cast<size_t>(source.shape().frames);
        for (auto* v : {&analysis.first_sums, &analysis.still_levels}) v->resize(F, 0.0);
        analysis.own_counts.resize(F, 0);
        refine_.keep_buffers(keep);
        scratch_.keep(keep);
    }
    // Frame t of I_T read from the analysis' parked frames.
    void frame(int64_t t, const std::function<void(int64_t, const float*)>& park) {
        auto scratch = scratch_.borrow();
        scratch->model.resize(static_cast<size_t>(source_.shape().pixels() * source_.shape().channels));
        analysis_.temporal->read_rows(t, 0, source_.shape().height, scratch->model.data());
        make(t, scratch->model.data(), *scratch, park);
    }
    // Frame t of I_T as the rebuild hands it on.
    void frame(int64_t t, const float* model, const std::function<void(int64_t, const float*)>& park) {
        auto scratch = scratch_.borrow();
        make(t, model, *scratch, park);
    }

private:
    static std::vector<uint8_t> moving_mask(const HybridAnalysis& analysis) {
        std::vector<uint8_t> moving(analysis.grown.size(), 0);
        for (size_t p = 0; p < moving.size(); ++p) moving[p] = analysis.grown[p] > 0.0f ? 1 : 0;
        return moving;
    }
    void make(int64_t t, const float* model, FirstPassScratch& scratch, const std::function<void(int64_t, const float*)>& park) {
        const Shape& s = source_.shape();
        const int64_t P = s.pixels(), C = s.channels, frame_samples = P * C;
        std::vector<float>& estimate = scratch.estimate;
        estimate.assign(model, model + frame_samples);
        refine_.apply(t, estimate.data(), s, source_.attributes());
        if (!own_first_.never()) {
            std::vector<float>& own_frame = scratch.own;
            own_frame.resize(static_cast<size_t>(frame_samples));
            read_input(source_, analysis_, t, own_frame.data());  // every row
            analysis_.own_counts[static_cast<size_t>(t)] = own_first_.apply(t, own_frame.data(), model, estimate.data(), scratch.diffusion);
        }
        analysis_.first_sums[static_cast<size_t>(t)] = positive_sum(estimate.data(), frame_samples);
        double level = 0;
        for (int64_t p = 0; p < P; ++p)
            if (!moving_[static_cast<size_t>(p)])
                for (int64_t c = 0; c < C; ++c) {
                    const float v = estimate[static_cast<size_t>(p * C + c)];
                    if (v > 0 && std::isfinite(v)) level += v;
                }
        analysis_.still_levels[static_cast<size_t>(t)] = level;
        park(t, estimate.data());
    }

    const FrameSource& source_;
    HybridAnalysis& analysis_;
    std::vector<uint8_t> moving_;
    OwnFirstPass own_first_;
    FrameStagePool refine_;
    WorkspacePool<FirstPassScratch> scratch_;
};

}  // namespace

LowRankOptions hybrid_part_options(const std::string& name, const ParamSet& hybrid_params) {
    ParamSet p = create_filter(name)->params();  // the part's own defaults for what the hybrid does not set
    for (const char* shared : kShared) p.set_string(shared, hybrid_params.get_string(shared));
    const LowRankModel model = name == "error-threshold" ? LowRankModel::PerPixel
                               : name == "moving-basis"  ? LowRankModel::Moving
                                                         : LowRankModel::Global;
    LowRankOptions o = low_rank_options(p, model);
    if (model == LowRankModel::Moving) {  // the study's window: mb_half_width frames a side, sigma half of it
        o.moving.half_width = hybrid_params.get_int("mb_half_width");
        o.moving.sigma = static_cast<double>(o.moving.half_width) / 2.0;
    }
    return o;
}

HybridStageOptions hybrid_stage_options(const ParamSet& p, bool prefiltered) {
    HybridStageOptions o;
    o.temporal = hybrid_part_options(p.get_string("temporal"), p);
    o.still = hybrid_part_options("pca", p);
    o.alpha.components = static_cast<int>(p.get_int("components"));
    o.signal_components = p.get_string("component_selection") == "signal";
    o.alpha.local_noise = p.get_string("alpha_noise") == "local";
    o.alpha.ignore_global_light = p.get_string("global_light") == "ignore";
    o.alpha.low = p.get_float("alpha_low");
    o.alpha.high = p.get_float("alpha_high");
    o.alpha.window = static_cast<int>(p.get_int("alpha_window"));
    if (!(o.alpha.high > o.alpha.low)) throw Error(Status::InvalidArgument, "alpha_high must be above alpha_low");
    o.change = temporal_change_options(p, prefiltered);
    o.still_fraction = p.get_float("still_fraction");
    o.mc_dilate = static_cast<int>(p.get_int("mc_dilate"));
    o.mc.half_width = static_cast<int>(p.get_int("mc_half_width"));
    o.mc.sigma = p.get_float("mc_sigma");
    o.mc.flow = parse_flow_preset(p.get_string("mc_flow"));
    // Linear samples: a weighted mean of unbiased samples is unbiased, where a mean of their logs
    // comes back darker (Jensen); the weights still judge agreement in log units.
    o.mc.transform = ValueTransform::None;
    o.single_frame = diffusion_options(p);
    o.passes.aux_threshold = p.get_float("aux_threshold");
    o.passes.vector_drift = p.get_float("vector_drift");
    return o;
}

bool hybrid_streams(const ParamSet& p) {
    return p.get_string("motion_compensation") == "auto" && p.get_int("shared_basis") == 1;
}

HybridStage::HybridStage(HybridStageOptions options)
    : options_(std::move(options)), refine_(postfilter_params(kRefinePostfilter, kRefinePostfilterParams)) {}

Footprint HybridStage::footprint() const {
    Footprint f;
    f.reach = TemporalReach::Shot;  // the statistics; then a window of mc_half_width frames a side
    f.window_half = options_.mc.half_width;
    f.halo = std::max<int64_t>(TemporalChange::kHalo, options_.alpha.window / 2);
    f.passes = 4;  // the Gram, alpha's light fit, the energies and scores, the coefficients; then the window
    f.streams = true;
    return f;
}

double HybridStage::analysis_bytes(const Shape& s) const {
    // alpha's energies and tails, the change test's centres and noise (double) and departures, the
    // row sums box_mean pools alpha's planes through (double), three float maps, and the halo rows of
    // a band.
    const double P = static_cast<double>(s.pixels());
    return P * (5 * sizeof(double) + 3 * sizeof(float) + 2 + sizeof(uint32_t)) +
           2.0 * TemporalChange::kHalo * s.frames * s.width * s.channels * (sizeof(float) + sizeof(double));
}

double HybridStage::maps_bytes(const Shape& s) {
    // After the analysis: alpha (a result), the moving weight, its grown copy, the moving mask and the
    // indices of the moving pixels; the own first pass' weights, masks and indices, and the change
    // test it keeps (noise and centre per pixel, double, its departures and its map).
    return static_cast<double>(s.pixels()) * (3 * sizeof(float) + 1 + sizeof(int64_t) + OwnFirstPass::held_bytes_per_pixel() +
                                              2 * sizeof(double) + sizeof(uint32_t) + sizeof(float));
}

double HybridStage::first_pass_bytes(const Shape& s, int threads, bool keep) const {
    // Per thread while I_T is rebuilt: the first pass' copy of the frame, the noisy frame diffused on
    // its own, a diffusion's working set (two when kept from frame to frame: the light pass's and the
    // frame's own diffusion's) and the own first pass' test of I_T.
    const double frame = static_cast<double>(s.pixels()) * s.channels * sizeof(float);
    const double diffusions = (keep ? 2 : 1) * diffusion_working_bytes(s.pixels(), s.channels);
    return threads * (2 * frame + diffusions + OwnFirstPass::working_bytes(s));
}

double HybridStage::window_bytes(const Shape& s, int threads, bool keep, const GuideSources& passes) const {
    return window_bytes(s, threads, keep, passes.vectors != nullptr, flow_surfaces(passes));
}

double HybridStage::window_bytes(const Shape& s, int threads, bool keep, bool vectors, int surfaces) const {
    const double frame = static_cast<double>(s.pixels()) * s.channels * sizeof(float);
    const double frames = 2.0 * options_.mc.half_width + threads;  // the window of every frame being averaged
    // Each window frame: samples, guide, image. Each thread: I_T, then the first pass with the average's
    // own buffers, the flow and DIS's images, the light diffusion pass of the frame it hands on, and
    // the frame a window frame is read through: one after the other, or side by side when the thread
    // keeps them from frame to frame.
    const double refine = options_.refine_after ? diffusion_working_bytes(s.pixels(), s.channels) : 0.0;
    const double average = frame + AlignedAverager::working_bytes(s, s.pixels());
    const double per_thread = frame + (keep ? refine + average + frame : std::max({average, refine, frame}));
    // The renderer's passes: each window frame's vectors (4 floats a pixel); each thread, while a frame
    // enters, a frame of a surface pass (4 channels at most counted) and its guide (3 a pass).
    const double P = static_cast<double>(s.pixels());
    const double vector_frames = vectors ? frames * P * 4 * sizeof(float) : 0.0;
    const double surface_rows = surfaces > 0 ? threads * P * (4 + 3.0 * surfaces) * sizeof(float) : 0.0;
    return frames * (2 * frame + P) + threads * per_thread + maps_bytes(s) + vector_frames + surface_rows;
}

double HybridStage::rebuild_bytes(const Shape& s, int threads, bool keep) const {
    const LowRankStage temporal(options_.temporal);
    const int64_t rank = options_.temporal.per_pixel ? options_.temporal.max_rank : options_.temporal.known_rank;
    // The temporal model's own need while it rebuilds (its second pass' band, or the frames it emits).
    return temporal.held_bytes(s, rank, threads, 1) + first_pass_bytes(s, threads, keep) + maps_bytes(s);
}

double HybridStage::min_bytes(const Shape& s, int threads) const {
    (void)threads;  // the rebuild and the window run on fewer threads when the budget is tight
    const LowRankStage temporal(options_.temporal);
    const int64_t rank = options_.temporal.per_pixel ? options_.temporal.max_rank : options_.temporal.known_rank;
    // The passes: the temporal model, a band and the motion maps; the rebuild: the model, the maps and
    // the first pass made of each frame; the window. The last two on one thread at least.
    const double passes = temporal.pass_bytes(s, rank) + temporal.band_row_bytes(s) + analysis_bytes(s);
    // The renderer's passes named: their least band beside the maps (4 channels at most counted), and
    // the window's vectors.
    const PassMotionOptions& named = options_.passes;
    const bool pass_bands = (named.surfaces && named.named_surfaces > 0) || (named.named_vectors && named.vector_drift > 0);
    const double pass_band = pass_bands ? maps_bytes(s) + analysis_bytes(s) + least_pass_band_bytes(s) : 0.0;
    return std::max({passes, pass_band, rebuild_bytes(s, 1, false), window_min_bytes(s)});
}

void HybridStage::run(const FrameSource& source, const FrameConsumer& consume, const StageContext& ctx, Results& results) {
    const HybridAnalysis analysis = analyse(source, ctx, results, &consume);
    if (!analysis.still) window(source, analysis, 0, source.shape().frames, consume, ctx, results);
}

// A plan's phases: the passes, each chunk's first passes, the guides, the frames (hybrid_analysis_file.hpp).
void HybridStage::analyse_into(const FrameSource& source, const std::string& dir, const StageContext& ctx,
                               Results& results) const {
    save_hybrid_passes(analyse_passes(source, ctx, results, nullptr), source.shape(), dir, "");
}

void HybridStage::frame_pass_into(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                                  const std::string& dir, const StageContext& ctx, Results& results) const {
    (void)results;
    HybridAnalysis analysis = load_hybrid_passes(source.shape(), source.attributes(), options_.change, files.analysis, nullptr);
    if (analysis.still) return;  // the window hands the still scene's frames on
    FirstPassFiles out(dir, source.shape(), f0, f1);
    first_pass(source, analysis, f0, f1, [&](int64_t t, const float* pixels) { out.write(t, pixels); }, ctx);
    out.finish(analysis);
}

void HybridStage::shot_pass_into(const FrameSource& source, const WindowedFiles& files, const std::string& dir,
                                 const StageContext& ctx, Results& results) const {
    HybridAnalysis analysis = load_hybrid_passes(source.shape(), source.attributes(), options_.change, files.analysis, nullptr);
    if (analysis.still) return;
    load_first_passes(source.shape(), source.attributes(), files.passes, analysis);
    guides(source.shape(), analysis, source.attributes(), ctx, results);
    save_guides(analysis, source.shape(), dir);
}

void HybridStage::frames_from(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                              const FrameConsumer& consume, const StageContext& ctx, Results& results) const {
    HybridAnalysis analysis = load_hybrid_passes(source.shape(), source.attributes(), options_.change, files.analysis, nullptr);
    if (!analysis.still) {
        load_first_passes(source.shape(), source.attributes(), files.passes, analysis);
        load_guides(source.shape(), source.attributes(), files.shot_pass, analysis);
    }
    window(source, analysis, f0, f1, consume, ctx, results);
}

HybridAnalysis HybridStage::analyse(const FrameSource& source, const StageContext& ctx, Results& results,
                                    const FrameConsumer* still_output) const {
    // Each frame's first pass is made as the rebuild hands its I_T on (on the rebuild's threads, the
    // frame in hand), the same as first_pass makes it from the parked frame.
    auto first = std::make_unique<ScratchFrames>(source.shape(), source.attributes());
    ScratchFrames& parked = *first;
    const auto park = [&](int64_t t, const float* pixels) { parked.write_frame(t, pixels); };
    std::unique_ptr<FirstPasses> passes;
    const ModelHook hook = [&](HybridAnalysis& maps, bool keep) {
        passes = std::make_unique<FirstPasses>(source, maps, options_, refine_, keep);
        return std::function<void(int64_t, const float*)>([&](int64_t t, const float* model) { passes->frame(t, model, park); });
    };
    HybridAnalysis analysis = analyse_passes(source, ctx, results, still_output, &hook);
    passes.reset();  // the rebuild's threads' buffers; the window counts its own (window_bytes)
    if (analysis.still) return analysis;
    analysis.first_pass = first.get();
    analysis.held.push_back(std::move(first));
    guides(source.shape(), analysis, source.attributes(), ctx, results);
    return analysis;
}

HybridAnalysis HybridStage::analyse_passes(const FrameSource& source, const StageContext& ctx, Results& results,
                                           const FrameConsumer* still_output, const ModelHook* each_model) const {
    const Shape& s = source.shape();
    const int64_t F = s.frames, P = s.pixels(), C = s.channels, H = s.height, W = s.width;
    const Progress none;
    const Progress& progress = ctx.progress ? *ctx.progress : none;
    const LowRankStage temporal(options_.temporal), still(options_.still);
    StageContext inner = ctx;
    inner.budget_bytes = ctx.budget_bytes - analysis_bytes(s);
    HybridAnalysis analysis;

    // 1. Statistics. The Gram, and each frame's light level for the change test, in one read.
    auto change_test = std::make_unique<TemporalChange>(s, options_.change);
    TemporalChange& change = *change_test;
    const bool test_change = options_.change.z_threshold > 0;
    const Progress gram_progress = part_of(progress, 0.0, 0.1);
    inner.progress = &gram_progress;
    LowRankStatistics stats = temporal.statistics(
        source, inner, test_change ? BandVisitor([&](const Sequence& band, int64_t y0) { change.add_levels(band, y0); })
                                   : BandVisitor());
    change.finish_levels();
    const LowRankStatistics::Group& group = stats.groups.front();  // streamed only with one shared basis
    const TemporalBasis basis = basis_from_gram(std::vector<double>(group.gram), F, group.series);
    const RankChoice signal = gavish_donoho_rank(basis.eigenvalues, basis.series, basis.frames);
    GlobalMotionOptions alpha_options = options_.alpha;
    // Components below the noise threshold are noise, and PCA aligns them with the noisiest pixels
    // (a few outlier samples): their energy piles up there and looks like motion.
    if (options_.signal_components) alpha_options.components = static_cast<int>(std::min<int64_t>(alpha_options.components, signal.rank));
    auto alpha_analysis = std::make_unique<GlobalMotionMap>(basis, signal.noise_sigma, alpha_options, H, W, group.group.count);
    GlobalMotionMap& alpha_map = *alpha_analysis;

    // Then two reads of bands with the change test's halo: the light fit and the pixels' noise, then
    // the energies and the scores. A kept band (the shot fits) is not read again.
    const int64_t halo = TemporalChange::kHalo;
    const int64_t rows = stats.keep ? H : std::max<int64_t>(1, stats.rows - 2 * halo);
    const int64_t bands = (H + rows - 1) / rows;
    std::vector<float> buffer;
    const auto each_band = [&](double at, double span, const char* stage,
                               const std::function<void(PreparedSeries&, const Sequence&, int64_t, int64_t, int64_t)>& body) {
        for (int64_t b = 0; b < bands; ++b) {
            progress.report(at + span * b / bands, stage);
            if (stats.keep) {
                body(stats.series(0, *stats.kept_band, 0), *stats.kept_band, 0, H, 0);
                continue;
            }
            const int64_t y0 = b * rows, y1 = std::min(H, y0 + rows);
            const int64_t a = std::max<int64_t>(0, y0 - halo), e = std::min(H, y1 + halo);
            const auto band = band_view(source, a, e, buffer, ctx.threads, {progress, at + span * b / bands, 0, stage});
            const auto own_rows = rows_of_band(*band, y0 - a, y1 - y0);
            body(stats.series(0, *own_rows, y0), *band, y0, y1, y0 - a);
            stats.cached[0].reset();  // it borrowed this band
        }
    };
    if (alpha_map.needs_light_fit() || test_change)
        each_band(0.1, 0.1, "motion", [&](PreparedSeries& series, const Sequence& band, int64_t y0, int64_t y1, int64_t top) {
            if (alpha_map.needs_light_fit()) series.read({none}, [&](const PreparedTile& t) { alpha_map.fit_light(t); });
            if (test_change) change.add_noise(band, y0, y1, top);
        });
    alpha_map.finish_light_fit();
    change.finish_noise();
    each_band(0.2, 0.1, "motion", [&](PreparedSeries& series, const Sequence& band, int64_t y0, int64_t y1, int64_t top) {
        series.read({none}, [&](const PreparedTile& t) { alpha_map.add_energy(t, y0 * W); });
        if (test_change) change.add_scores(band, y0, y1, top);
    });
    if (test_change) change.finish_scores();
    buffer = std::vector<float>();
    const std::shared_ptr<Sequence> alpha = alpha_map.alpha();
    // Where things move: 1 - alpha, raised where the temporal-change test says so.
    auto weight = std::make_shared<Sequence>(alpha->shape());
    for (int64_t p = 0; p < P; ++p) weight->at(0, p / W, p % W, 0) = 1.0f - alpha->at(0, p / W, p % W, 0);
    // Where the change test saw what alpha did not, the frame's own diffusion is the first pass.
    std::vector<float> own_weight;
    if (test_change) {
        own_weight = crossing_weight(*change.map(), *alpha);
        combine_max(*weight, *change.map());
    }
    // And where the renderer's passes say so (read in bands as the input was; none held past here).
    if (passes_show_motion(ctx.passes, options_.passes)) {
        // A kept band (the shot fits) stays held with its prepared tiles: counted as the statistics
        // pass counted it when it chose to keep it.
        const double kept = stats.keep && !source.in_memory() ? static_cast<double>(H) * temporal.band_row_bytes(s) : 0.0;
        raise_by_passes(&weight->at(0, 0, 0, 0), s, ctx.passes, options_.passes, inner.budget_bytes - maps_bytes(s) - kept,
                        ctx.threads, {progress, 0.3, 0.0, "motion"});
    }
    alpha_analysis.reset();  // their per-pixel sums are not needed past here (maps_bytes)
    const double moving_share = mean_of_map(*weight);
    results.set("motion_fraction", moving_share);
    results.set_image("alpha", alpha);
    results.set("bands", static_cast<double>(stats.bands));

    FrameStagePool refine("postfilter", refine_);
    Results own;
    const auto park = [&] {
        auto frames = std::make_unique<ScratchFrames>(s, source.attributes());
        ScratchFrames* parked = frames.get();
        analysis.held.push_back(std::move(frames));
        return parked;
    };
    if (moving_share < options_.still_fraction) {
        // 2. A still scene: global PCA (automatic rank) from the Gram at hand is all it requires.
        analysis.still = true;
        const Progress rebuild = part_of(progress, 0.3, 0.7);
        inner.progress = &rebuild;
        if (still_output) {
            // Room for the light pass' buffers on every thread beside the model: they are kept.
            const double kept = ctx.threads * diffusion_working_bytes(s.pixels(), s.channels);
            refine.keep_buffers(still.min_bytes(s, ctx.threads) + kept <= inner.budget_bytes);
            still.reconstruct(source, std::move(stats), [&](int64_t t, float* pixels) {
                if (options_.refine_after) refine.apply(t, pixels, s, source.attributes());
                (*still_output)(t, pixels);
            }, inner, own);
        } else {
            ScratchFrames* frames = park();
            still.reconstruct(source, std::move(stats), [&](int64_t t, float* pixels) { frames->write_frame(t, pixels); },
                              inner, own);
            analysis.temporal = frames;
        }
        results.set("beta_source", "none (still scene)");
        results.set_image(kMotionPathResult, std::make_shared<Sequence>(Shape{1, H, W, 1}));  // followed no motion
        results.set("moving_basis_fraction", 0.0);
        results.set("diffusion_fraction", 0.0);
        results.copy(own, "rank", "temporal_rank");
        return analysis;
    }

    // 3. The moving pixels: the weight grown by a max filter. alpha is pooled over a box and ramps,
    // so along the rim of a moving region the temporal filter would keep part of the weight, and
    // there its per-pixel ranks keep the motion's noise (dark and bright speckles at 4 spp).
    cv::Mat grown(static_cast<int>(H), static_cast<int>(W), CV_32F);
    for (int64_t p = 0; p < P; ++p) grown.at<float>(static_cast<int>(p)) = weight->at(0, p / W, p % W, 0);
    if (options_.mc_dilate > 0)
        cv::dilate(grown, grown, cv::Mat::ones(2 * options_.mc_dilate + 1, 2 * options_.mc_dilate + 1, CV_8U));
    analysis.grown.assign(grown.ptr<float>(), grown.ptr<float>() + P);
    auto motion_path = std::make_shared<Sequence>(Shape{1, H, W, 1});
    std::copy(analysis.grown.begin(), analysis.grown.end(), &motion_path->at(0, 0, 0, 0));
    results.set_image(kMotionPathResult, motion_path);
    // The own first pass' inputs: the crossings, and the change test for its test of I_T (maps_bytes).
    analysis.crossings = std::move(own_weight);
    if (test_change) analysis.change = std::move(change_test);

    // The fireflies the statistics pass found, frame by frame: the temporal model never saw them, and
    // neither may the frame's own diffusion or the average along the flow, which read the input again
    // (else a firefly spreads to the frames aligned with its own).
    analysis.fireflies.resize(static_cast<size_t>(F));
    for (const TemporalOutlier& o : stats.fireflies.empty() ? std::vector<TemporalOutlier>() : stats.fireflies.front()) {
        const int64_t p = o.series / group.group.count, c = group.group.first + o.series % group.group.count;
        analysis.fireflies[static_cast<size_t>(o.frame)].emplace_back(p * C + c, static_cast<float>(o.value));
    }
    // I_T, frame by frame, parked. The model gets the budget and threads it had when the first
    // passes were made beside it (the same bands, the same numbers).
    ScratchFrames& temporal_frames = *park();
    const Progress rebuild = part_of(progress, 0.3, 0.05);
    inner.progress = &rebuild;
    inner.threads = fitting_threads(ctx, [&](int t) { return rebuild_bytes(s, t, false); });
    const bool keep_rebuild = rebuild_bytes(s, inner.threads, true) <= ctx.budget_bytes;
    inner.budget_bytes = ctx.budget_bytes - maps_bytes(s) - first_pass_bytes(s, inner.threads, keep_rebuild);
    const std::function<void(int64_t, const float*)> hook =
        each_model ? (*each_model)(analysis, keep_rebuild) : std::function<void(int64_t, const float*)>();
    temporal.reconstruct(source, std::move(stats), [&](int64_t t, float* pixels) {
        temporal_frames.write_frame(t, pixels);
        if (hook) hook(t, pixels);
    }, inner, own);
    analysis.temporal = &temporal_frames;
    for (const char* name : {"rank", "mean_rank"})
        if (own.has(name)) results.copy(own, name, std::string("temporal_") + name);
    results.set("beta_source", "none (motion compensation)");
    results.set("motion_compensation", ctx.passes.vectors       ? "the renderer's motion vectors"
                                       : flow_on_surfaces(ctx.passes) ? "optical flow on the albedo/normal passes"
                                                                      : "optical flow on the first pass");
    const int64_t moving_count = count_moving(analysis);
    results.set("aligned_fraction", static_cast<double>(moving_count) / static_cast<double>(P));
    results.set("moving_basis_fraction", 0.0);
    results.set("diffusion_fraction", 0.0);
    return analysis;
}

void HybridStage::first_pass(const FrameSource& source, HybridAnalysis& analysis, int64_t f0, int64_t f1,
                             const std::function<void(int64_t, const float*)>& park, const StageContext& ctx) const {
    const Progress none;
    const Progress& progress = ctx.progress ? *ctx.progress : none;
    // As many threads, and buffers kept from frame to frame, as when the first passes are made while
    // the model rebuilds I_T (rebuild_bytes).
    const int threads = fitting_threads(ctx, [&](int t) { return rebuild_bytes(source.shape(), t, false); });
    FirstPasses passes(source, analysis, options_, refine_, rebuild_bytes(source.shape(), threads, true) <= ctx.budget_bytes);
    parallel_for(f1 - f0, threads, [&](int64_t i) { passes.frame(f0 + i, park); }, {progress, 0.35, 0.15, "first pass"});
}

void HybridStage::guides(const Shape& s, HybridAnalysis& analysis, const Sequence& attributes, const StageContext& ctx,
                         Results& results) const {
    const int64_t F = s.frames, P = s.pixels(), H = s.height;
    const int64_t frame_samples = P * s.channels;
    const Progress none;
    const Progress& progress = ctx.progress ? *ctx.progress : none;
    double total = 0;
    for (double v : analysis.first_sums) total += v;
    const double mean = estimate_mean(total, F * frame_samples);
    // Each frame's light level where nothing moves (its first pass summed over the still pixels, over
    // the shot's mean of that sum), so the aligned averages follow a global light change; none
    // (constant) when under 5% of the frame is still, where frame sums would measure content, not light.
    const int64_t moving_count = count_moving(analysis);
    analysis.frame_gain.clear();
    if (P - moving_count >= P / 20) {
        double level_mean = 0;
        for (double l : analysis.still_levels) level_mean += l / static_cast<double>(F);
        analysis.frame_gain = analysis.still_levels;
        for (double& l : analysis.frame_gain) {
            if (!(level_mean > 0) || !(l > 0)) {
                analysis.frame_gain.clear();
                break;
            }
            l /= level_mean;
        }
    }

    // The flow images' scale: the guide's 99.5th percentile, in two reads of the guides. Each frame's
    // guide is made once, from its first pass, and parked for the second read and the window.
    // (On the albedo/normal passes the flow's images are the passes themselves: one read, no scale.)
    GuideScale quantile(frame_samples);
    auto parked = std::make_unique<ScratchFrames>(s, attributes);
    ScratchFrames& guide_frames = *parked;
    const bool on_surfaces = flow_on_surfaces(ctx.passes);
    for (const bool counting : {true, false}) {
        if (!counting && on_surfaces) break;
        const int64_t batch = std::max(1, ctx.threads);
        std::vector<std::vector<float>> guides(static_cast<size_t>(batch), std::vector<float>(static_cast<size_t>(frame_samples)));
        for (int64_t f0 = 0; f0 < F; f0 += batch) {
            const int64_t n = std::min(batch, F - f0);
            parallel_for(n, ctx.threads, [&](int64_t i) {
                float* guide = guides[static_cast<size_t>(i)].data();
                if (!counting) return guide_frames.read_rows(f0 + i, 0, H, guide);
                std::vector<float> estimate(static_cast<size_t>(frame_samples));
                analysis.first_pass->read_rows(f0 + i, 0, H, estimate.data());
                aligned_guide(estimate.data(), frame_samples, gain_of(analysis, f0 + i), mean, guide);
                guide_frames.write_frame(f0 + i, guide);
            }, {progress, 0.5 + (counting ? 0.0 : 0.025) + 0.025 * f0 / F, 0, "motion compensation"});
            for (int64_t i = 0; i < n && !on_surfaces; ++i) {
                if (counting) quantile.count(f0 + i, guides[static_cast<size_t>(i)].data());
                else quantile.collect(f0 + i, guides[static_cast<size_t>(i)].data());
            }
        }
        if (counting && !on_surfaces) quantile.finish_counting();
    }
    analysis.guide_scale = on_surfaces ? 1.0 : quantile.scale();
    analysis.guides = parked.get();
    analysis.held.push_back(std::move(parked));
    double own_share = 0;
    for (const int64_t n : analysis.own_counts) own_share += static_cast<double>(n) / static_cast<double>(F * P);
    results.set("own_first_pass_fraction", own_share);
}

void HybridStage::window(const FrameSource& source, const HybridAnalysis& analysis, int64_t f0, int64_t f1,
                         const FrameConsumer& consume, const StageContext& ctx, Results& results) const {
    const Shape& s = source.shape();
    const int64_t F = s.frames, P = s.pixels(), H = s.height, W = s.width, C = s.channels;
    const int64_t frame_samples = P * C;
    const Progress none;
    const Progress& progress = ctx.progress ? *ctx.progress : none;
    FrameStagePool refine("postfilter", refine_);
    const auto hand_on = [&](int64_t t, float* pixels) {
        if (options_.refine_after) refine.apply(t, pixels, s, source.attributes());
        consume(t, pixels);
    };
    if (f1 <= f0) return;
    if (analysis.still) {
        // The still scene's frames, parked by the analysis: the light pass, then on.
        const int threads = fitting_threads(ctx, [&](int t) {
            return t * (static_cast<double>(frame_samples) * sizeof(float) + diffusion_working_bytes(P, C));
        });
        refine.keep_buffers(true);
        parallel_for(f1 - f0, threads, [&](int64_t i) {
            std::vector<float> frame(static_cast<size_t>(frame_samples));
            analysis.temporal->read_rows(f0 + i, 0, H, frame.data());
            hand_on(f0 + i, frame.data());
        }, {progress, 0.3, 0.7, "frames"});
        return;
    }
    std::vector<int64_t> pixels;
    for (int64_t p = 0; p < P; ++p)
        if (analysis.grown[static_cast<size_t>(p)] > 0.0f) pixels.push_back(p);
    AlignedAverageOptions mc = options_.mc;
    mc.frame_gain = analysis.frame_gain;

    // 4. The window: frame t's moving pixels averaged along the flow over t - h .. t + h, blended into
    // I_T by the moving weight. Frames enter the window once and leave when no frame still needs them.
    const AlignedAverager averager(s, pixels, mc);
    std::map<int64_t, std::unique_ptr<WindowFrame>> window;
    AlignedWindow access;
    access.values = [&](int64_t f) { return window.at(f)->values.data(); };
    access.guide = [&](int64_t f) { return window.at(f)->guide.data(); };
    access.image = [&](int64_t f) { return window.at(f)->image.data(); };
    const GuideSources& passes = ctx.passes;
    const bool on_surfaces = flow_on_surfaces(passes);
    if (passes.vectors) access.vectors = [&](int64_t f) { return window.at(f)->vectors.data(); };
    const int window_threads = fitting_threads(ctx, [&](int t) { return window_bytes(s, t, false, passes); });
    // Where the budget holds them (window_bytes with keep), each thread keeps its frames, the average's
    // scratch and the light pass' buffers from frame to frame.
    const bool keep = window_bytes(s, window_threads, true, passes) <= ctx.budget_bytes;
    refine.keep_buffers(keep);
    struct Worker {
        std::vector<float> frame, out, aligned;
        AlignedScratch scratch;
    };
    std::vector<Worker> kept(keep ? static_cast<size_t>(window_threads) : 0);
    const int64_t h = mc.half_width, batch = window_threads;
    std::vector<double> frame_weight(static_cast<size_t>(F), 0.0);
    for (int64_t t0 = f0; t0 < f1; t0 += batch) {
        const int64_t t1 = std::min(f1, t0 + batch);
        const int64_t lo = std::max<int64_t>(0, t0 - h), hi = std::min(F - 1, t1 - 1 + h);
        window.erase(window.begin(), window.lower_bound(lo));
        std::vector<int64_t> entering;
        for (int64_t f = lo; f <= hi && !pixels.empty(); ++f)
            if (!window.count(f)) {
                window.emplace(f, std::make_unique<WindowFrame>());
                entering.push_back(f);
            }
        const double at = 0.55 + 0.45 * static_cast<double>(t0 - f0) / static_cast<double>(f1 - f0);
        parallel_for_workers(static_cast<int64_t>(entering.size()), window_threads, [&](int64_t i, int worker) {
            const int64_t f = entering[static_cast<size_t>(i)];
            WindowFrame& w = *window.at(f);
            std::vector<float> own_frame;
            std::vector<float>& frame = keep ? kept[static_cast<size_t>(worker)].frame : own_frame;
            frame.resize(static_cast<size_t>(frame_samples));
            w.values.resize(frame.size());
            w.guide.resize(frame.size());
            w.image.resize(static_cast<size_t>(P));
            read_input(source, analysis, f, frame.data());
            aligned_values(frame.data(), frame_samples, gain_of(analysis, f), mc.transform, w.values.data());
            analysis.guides->read_rows(f, 0, H, w.guide.data());
            if (on_surfaces) {
                std::vector<float> guide;
                surfaces_image(passes, f, s, frame, guide, w.image.data());
            } else {
                flow_image(w.guide.data(), W, H, C, analysis.guide_scale, w.image.data());
            }
            if (passes.vectors) frame_vectors(*passes.vectors, f, s, frame, w.vectors);
        }, {progress, at, 0, "motion compensation"});
        parallel_for_workers(t1 - t0, window_threads, [&](int64_t i, int worker) {
            const int64_t t = t0 + i;
            Worker own;  // its buffers go with this frame unless the budget keeps them (window_bytes)
            Worker& wk = keep ? kept[static_cast<size_t>(worker)] : own;
            std::vector<float>& out = wk.out;
            out.resize(static_cast<size_t>(frame_samples));
            analysis.temporal->read_rows(t, 0, H, out.data());
            if (!pixels.empty()) {
                std::vector<float>& aligned = wk.aligned;
                aligned.resize(out.size());
                analysis.first_pass->read_rows(t, 0, H, aligned.data());  // a pixel with nothing to average keeps it
                frame_weight[static_cast<size_t>(t)] = averager.average(t, access, aligned.data(), wk.scratch);
                for (const int64_t p : pixels) {
                    const float w = analysis.grown[static_cast<size_t>(p)];
                    for (int64_t c = 0; c < C; ++c) {
                        float& o = out[static_cast<size_t>(p * C + c)];
                        o += w * (aligned[static_cast<size_t>(p * C + c)] - o);
                    }
                }
                if (!keep) {  // gone before the frame's diffusion (window_bytes)
                    std::vector<float>().swap(wk.aligned);
                    wk.scratch = AlignedScratch();
                }
            }
            hand_on(t, out.data());
        }, {progress, at, 0.45 * static_cast<double>(t1 - t0) / static_cast<double>(f1 - f0), "motion compensation"});
    }
    // The mean summed weight of the averaged pixel-frames of these frames.
    double weights = 0;
    for (double v : frame_weight) weights += v;
    results.set("aligned_frames", pixels.empty() ? 0.0 : weights / static_cast<double>((f1 - f0) * static_cast<int64_t>(pixels.size())));
}

}  // namespace statfilter
