// The study's hybrid: I = I_T * alpha + I_MB * (1 - alpha) * s + I_SF * (1 - alpha) * (1 - s).
// I_T is a global temporal filter, I_MB the moving basis, I_SF single-frame diffusion; alpha is the
// global motion map and s comes from the local motion mask beta. The study's slide multiplies I_MB
// by beta (reading "literal"); the other reading gives the moving-right-now pixels to the
// single-frame filter (reading "safe", s = 1 - beta). Both are here, measured in docs/methods.md.
// I_MB and I_SF are computed only where their weight is non-zero: the moving basis on a compact
// sequence of just those pixels, diffusion on each frame's bounding box of them (plus a halo as wide
// as the diffusion reaches). Where things move is 1 - alpha, raised where a temporal-change test
// (an object crossing a pixel in a frame or two, which alpha misses) or the renderer's motion vectors
// (the named input "vectors", Cycles' Vector pass) say so. When (almost) nothing moves, the basis computed for alpha
// reconstructs the sequence directly (global PCA, automatic rank): a still scene costs about what
// `pca` costs. By default (motion_compensation=auto) the moving pixels get the motion-compensated
// average instead of I_MB and I_SF: each frame's neighbours warped onto it along optical flow, on the
// renderer's albedo/normal passes when given, else on a first pass, or along the renderer's vectors when
// given (statfilter/motion_compensation.hpp); I = I_T * (1 - m) + I_MC * m, m the moving weight grown by
// a max filter (mc_dilate).
#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "filters/builtin_filters.hpp"
#include "filters/frame_stages.hpp"
#include "filters/hybrid_stage.hpp"
#include "filters/low_rank_reconstruction.hpp"
#include "filters/motion_analysis.hpp"
#include "filters/own_first_pass.hpp"
#include "filters/temporal_params.hpp"
#include "pipeline/parallel.hpp"
#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/error.hpp"
#include "statfilter/filter_registry.hpp"
#include "statfilter/motion_compensation.hpp"

namespace statfilter {
namespace {

class HybridFilter final : public Filter {
public:
    HybridFilter() : Filter(make_params()) {
        for (const char* pass : {"albedo", "normal", "vectors"}) accept_input(pass);
        declare_image_result("alpha");
        declare_image_result("beta", ImageFrames::PerFrame);
    }

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {
            choice_param("temporal", "error-threshold", {"error-threshold", "pca"},
                         "the global temporal filter used where alpha says still"),
            choice_param("reading", "safe", {"safe", "literal"},
                         "with motion_compensation=off: safe = moving basis where no local motion now, diffusion "
                         "where there is; literal (the study's slide) = moving basis where beta says motion"),
            int_param("mb_half_width", "8", 1, 10000, "moving basis: window half-width in frames"),
            float_param("still_fraction", "0.01", 0, 1,
                        "below this share of moving pixels (the mean moving weight: 1 - alpha, raised by the temporal-change "
                        "test and the motion vectors) only global PCA runs: a still scene"),
            ParamSpec{"single_frame", ParamType::String, "diffusion",
                      "with motion_compensation=off, the single-frame stage: diffusion (on the moving pixels' "
                      "bounding boxes only) or any single-frame filter or plugin, e.g. oidn (on the frames that need it)",
                      0, 0, {}, false, ""},
            choice_param("motion_compensation", "auto", {"auto", "off"},
                         "auto: average each moving pixel along optical flow (on the albedo/normal passes when "
                         "given, else on a first pass) instead of the moving basis and diffusion; off: never"),
            int_param("mc_half_width", "8", 1, 10000, "motion compensation: frames averaged on each side"),
            float_param("mc_sigma", "0.1", 1e-6, 1e9,
                        "motion compensation: mismatch of a warped sample with the frame (first pass, relative "
                        "log units, beyond what the frame takes within half a pixel) at which its weight falls "
                        "to exp(-1/2)"),
            int_param("mc_dilate", "4", 0, 1000,
                      "motion compensation: the moving weight 1 - alpha is grown by a max filter of this radius "
                      "(pixels), so the rim of a moving region is aligned too"),
            choice_param("mc_flow", "medium", {"ultrafast", "fast", "medium"},
                         "motion compensation: OpenCV DIS optical-flow preset, faster to more accurate"),
        };
        for (auto& c : motion_params()) p.push_back(c);
        for (auto& c : diffusion_params()) p.push_back(c);
        for (auto& c : temporal_common_params()) {
            // The blend leaves spatially white noise on a smooth signal: a light diffusion pass after it
            // is part of the hybrid by default (postfilter= turns it off).
            if (c.name == "postfilter") c.default_value = kRefinePostfilter;
            if (c.name == "postfilter_params") c.default_value = kRefinePostfilterParams;
            if (c.name == "prefilter_order") c.default_value = kHybridPrefilterOrder;
            p.push_back(c);
        }
        return p;
    }

    // With motion compensation the hybrid streams (filters/hybrid_stage.hpp), the renderer's passes
    // beside its input; otherwise it holds the shot.
    std::unique_ptr<StreamStage> stream_stage() const override {
        if (!hybrid_streams(params())) return nullptr;
        HybridStageOptions options = hybrid_stage_options(params(), temporal_sees_prefilter(params()));
        count_named_passes(*this, params(), options.passes);
        return std::make_unique<HybridStage>(std::move(options));
    }
    // In memory, besides input and output: the first pass, the average's transformed samples and
    // guide, and the input with its fireflies replaced.
    double resident_copies() const override { return 4; }
    Footprint footprint() const override {
        auto stage = stream_stage();
        return stage ? stage->footprint() : Footprint{};
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        // The renderer's passes, read and checked before any work, used or not.
        const GuidePasses passes = guide_passes(*this, input, params());
        if (auto stage = stream_stage()) {
            const GuideMemorySources sources = guide_memory_sources(passes);
            run_in_memory(*stage, input, output, progress, params().get_float("memory_mb") * 1024.0 * 1024.0, mutable_results(),
                          sources.view);
            return;
        }
        const Shape& s = input.shape();
        const TemporalSetup setup = temporal_setup(params(), input);
        // One basis serves alpha and, when nothing moves, the reconstruction itself.
        PreparedSeries series(input, ChannelSelection::all(s), setup.prep, setup.budget_bytes, 2);
        const TemporalBasis basis = compute_temporal_basis(series, {progress, 0.0, 0.2, "motion"});
        MotionMaps maps;
        maps.alpha = compute_alpha(series, basis, params(), {progress, 0.2, 0.1, "motion"});
        // Where things move: alpha, the temporal-change test and the renderer's vectors when given.
        std::vector<float> crossings;
        std::unique_ptr<TemporalChange> change;
        const auto weight = moving_weight(input, *maps.alpha, passes, params(), &crossings, &change);
        const double moving = mean_of_map(*weight);
        mutable_results().set("motion_fraction", moving);
        mutable_results().set_image("alpha", maps.alpha);
        if (moving < params().get_float("still_fraction") && setup.shared_basis) {
            // A still scene: global PCA (automatic rank) from the basis at hand is all it requires.
            const RankChoice rank = gavish_donoho_rank(basis.eigenvalues, basis.series, basis.frames);
            reconstruct_low_rank(series, output, basis, rank.rank, nullptr, {progress, 0.3, 0.7, "reconstruct"});
            mutable_results().set("beta_source", "none (still scene)");
            mutable_results().set("moving_basis_fraction", 0.0);
            mutable_results().set("diffusion_fraction", 0.0);
            mutable_results().set("temporal_rank", static_cast<double>(rank.rank));
            return;
        }
        if (params().get_string("motion_compensation") == "auto") {
            run_motion_compensated(input, series.outliers(), output, *weight, std::move(crossings), change.get(), passes,
                                   progress);
            return;
        }
        compute_beta(input, passes, params(), maps);

        Sequence base(s);
        run_temporal(input, base, {progress, 0.3, 0.3, "temporal"});

        // Weights of the moving basis and of diffusion per pixel and frame.
        const bool literal = params().get_string("reading") == "literal";
        const int64_t P = s.pixels();
        std::vector<float> w_mb(static_cast<size_t>(s.frames * P)), w_sf(w_mb.size());
        std::vector<int64_t> mb_pixels;
        for (int64_t p = 0; p < P; ++p) {
            const float moving = weight->at(0, p / s.width, p % s.width, 0);
            bool needs_mb = false;
            for (int64_t f = 0; f < s.frames; ++f) {
                const float beta = maps.beta->at(f, p / s.width, p % s.width, 0);
                const float safe = literal ? beta : 1.0f - beta;
                w_mb[f * P + p] = moving * safe;
                w_sf[f * P + p] = moving * (1.0f - safe);
                needs_mb = needs_mb || w_mb[f * P + p] > 0;
            }
            if (needs_mb) mb_pixels.push_back(p);
        }
        output.copy_samples_from(base);
        const auto mb = moving_basis_on(input, mb_pixels, progress);
        const std::string single_frame = params().get_string("single_frame");
        const double sf_fraction = single_frame == "diffusion" ? blend_diffusion(input, w_sf, output, progress)
                                                               : blend_single_frame(single_frame, input, w_sf, output, progress);
        for (size_t i = 0; i < mb_pixels.size(); ++i) {
            const int64_t p = mb_pixels[i], y = p / s.width, x = p % s.width;
            for (int64_t f = 0; f < s.frames; ++f) {
                const float w = w_mb[f * P + p];
                for (int64_t c = 0; c < s.channels; ++c)
                    output.at(f, y, x, c) += w * (mb->at(f, 0, static_cast<int64_t>(i), c) - base.at(f, y, x, c));
            }
        }
        mutable_results().set("beta_source", maps.beta_source);
        mutable_results().set("moving_basis_fraction", static_cast<double>(mb_pixels.size()) / P);
        mutable_results().set("diffusion_fraction", sf_fraction);
        mutable_results().set_image("beta", maps.beta);
        progress.report(1.0, "hybrid");
    }

private:
    // The frame's own diffusion as the first pass (contiguous: made here) where the streamed stage
    // puts it (filters/own_first_pass.hpp), I_T being `model`. Returns the share of pixel-frames.
    double own_first_pass(const Sequence& input, const Sequence& model, const OwnFirstPass& own, Sequence& first_pass) const {
        const Shape& s = input.shape();
        const int64_t P = s.pixels(), C = s.channels;
        if (own.never()) return 0.0;
        std::vector<int64_t> counts(static_cast<size_t>(s.frames), 0);
        const Progress none;
        const int threads = resolve_threads(0);
        std::vector<DiffusionWorkspace> workspaces(static_cast<size_t>(worker_count(s.frames, threads)));
        parallel_for_workers(s.frames, threads, [&](int64_t f, int worker) {
            std::vector<float> frame(static_cast<size_t>(P * C)), temporal(frame.size());  // views may be strided
            for (int64_t p = 0; p < P; ++p)
                for (int64_t c = 0; c < C; ++c) {
                    frame[static_cast<size_t>(p * C + c)] = input.at(f, p / s.width, p % s.width, c);
                    temporal[static_cast<size_t>(p * C + c)] = model.at(f, p / s.width, p % s.width, c);
                }
            counts[static_cast<size_t>(f)] = own.apply(f, frame.data(), temporal.data(), &first_pass.at(f, 0, 0, 0),
                                                   workspaces[static_cast<size_t>(worker)]);
        }, {none});
        double share = 0;
        for (const int64_t n : counts) share += static_cast<double>(n) / static_cast<double>(s.frames * P);
        return share;
    }

    // I_T, the global temporal filter (`temporal`), into output; its rank results as temporal_*.
    void run_temporal(const Sequence& input, Sequence& output, const ProgressSpan& span) {
        LowRankStage temporal(hybrid_part_options(params().get_string("temporal"), params()));
        Results own;
        run_in_memory(temporal, input, output, Progress([&](double f, const char*) {
            span.report(f);
            return true;
        }), params().get_float("memory_mb") * 1024.0 * 1024.0, own);
        for (const char* name : {"rank", "mean_rank"})
            if (own.has(name)) mutable_results().copy(own, name, std::string("temporal_") + name);
    }

    // I_T where nothing moves, the motion-compensated average where things move (`moving`, 1 = moving),
    // aligned along the renderer's vectors when given, else along optical flow.
    // `fireflies`: what the statistics found in input (all channels), kept out of the frame's own
    // diffusion and of the average along the flow as the temporal model keeps them out (else a
    // firefly spreads to the frames aligned with its own, as in the streamed stage).
    void run_motion_compensated(const Sequence& noisy, const std::vector<TemporalOutlier>& fireflies, Sequence& output,
                                const Sequence& moving_map, std::vector<float> crossings, const TemporalChange* change,
                                const GuidePasses& guides, const Progress& progress) {
        const Sequence* vectors = guides.vectors;
        const Shape& s = noisy.shape();
        run_temporal(noisy, output, {progress, 0.3, 0.15, "temporal"});
        std::unique_ptr<Sequence> cleaned;
        if (!fireflies.empty()) {
            cleaned = std::make_unique<Sequence>(s);
            cleaned->copy_samples_from(noisy);
            replace_temporal_outliers(*cleaned, ChannelSelection::all(s), fireflies);
        }
        const Sequence& input = cleaned ? *cleaned : noisy;
        // The first pass the warped samples are checked against: I_T with the light diffusion pass.
        // The aligned averages then overwrite it in place (it is read in full first): one frame-sized
        // copy of the sequence less at production sizes.
        auto refine = create_filter(kRefinePostfilter);
        set_param_list(refine->params(), kRefinePostfilterParams, "first pass");
        Sequence aligned(s);
        refine->execute(output, aligned, Progress([&](double f, const char*) {
            progress.report(0.45 + 0.05 * f, "first pass");
            return true;
        }));
        // The moving weight, grown by a max filter: alpha is pooled over a box and ramps, so
        // along the rim of a moving region the temporal filter would keep part of the weight, and
        // there its per-pixel ranks keep the motion's noise (dark and bright speckles at 4 spp).
        cv::Mat weight(static_cast<int>(s.height), static_cast<int>(s.width), CV_32F);
        for (int64_t p = 0; p < s.pixels(); ++p)
            weight.at<float>(static_cast<int>(p / s.width), static_cast<int>(p % s.width)) = moving_map.at(0, p / s.width, p % s.width, 0);
        const int grow = static_cast<int>(params().get_int("mc_dilate"));
        if (grow > 0) cv::dilate(weight, weight, cv::Mat::ones(2 * grow + 1, 2 * grow + 1, CV_8U));
        std::vector<uint8_t> moving(static_cast<size_t>(s.pixels()));
        for (int64_t p = 0; p < s.pixels(); ++p)
            moving[static_cast<size_t>(p)] = weight.at<float>(static_cast<int>(p / s.width), static_cast<int>(p % s.width)) > 0.0f;
        const OwnFirstPass own(s, std::move(crossings), change, moving, params().get_int("mc_half_width"),
                               diffusion_options(params()));
        mutable_results().set("own_first_pass_fraction", own_first_pass(input, output, own, aligned));
        // The passes guide the flow; with the renderer's vectors there is no flow to guide.
        const auto passes = guides.surfaces() && !vectors ? make_pass_guide(guides.albedo, guides.normal) : nullptr;
        AlignedAverageOptions options;
        options.half_width = static_cast<int>(params().get_int("mc_half_width"));
        options.sigma = params().get_float("mc_sigma");
        options.flow = parse_flow_preset(params().get_string("mc_flow"));
        // Linear samples: a weighted mean of unbiased samples is unbiased, where a mean of their logs
        // comes back darker (Jensen); the weights still judge agreement in log units.
        options.transform = ValueTransform::None;
        options.frame_gain = still_light_levels(aligned, moving);
        options.vectors = vectors;
        // A pixel the other frames do not reach (or nothing finite) keeps the first pass.
        const AlignedAverageStats stats = aligned_average(input, aligned, passes.get(), moving, options, aligned,
                                                          {progress, 0.5, 0.5, "motion compensation"});
        for (int64_t p = 0; p < s.pixels(); ++p) {
            if (!moving[static_cast<size_t>(p)]) continue;
            const int64_t y = p / s.width, x = p % s.width;
            const float w = weight.at<float>(static_cast<int>(y), static_cast<int>(x));
            for (int64_t f = 0; f < s.frames; ++f)
                for (int64_t c = 0; c < s.channels; ++c) output.at(f, y, x, c) += w * (aligned.at(f, y, x, c) - output.at(f, y, x, c));
        }
        mutable_results().set("beta_source", "none (motion compensation)");
        mutable_results().set("motion_compensation", vectors  ? "the renderer's motion vectors"
                                                     : passes ? "optical flow on the albedo/normal passes"
                                                              : "optical flow on the first pass");
        mutable_results().set("aligned_fraction", stats.pixel_fraction);
        mutable_results().set("aligned_frames", stats.mean_frames);
        mutable_results().set("moving_basis_fraction", 0.0);
        mutable_results().set("diffusion_fraction", 0.0);
        progress.report(1.0, "hybrid");
    }

    // Each frame's light level where nothing moves (its first pass summed over the still pixels, over
    // the sequence's mean of that sum), so the aligned averages follow a global light change; empty
    // (constant) when under 5% of the frame is still, where frame sums would measure content, not light.
    static std::vector<double> still_light_levels(const Sequence& first_pass, const std::vector<uint8_t>& moving) {
        const Shape& s = first_pass.shape();
        const auto still = static_cast<int64_t>(std::count(moving.begin(), moving.end(), uint8_t{0}));
        if (still < s.pixels() / 20) return {};
        std::vector<double> level(static_cast<size_t>(s.frames), 0.0);
        double mean = 0;
        for (int64_t f = 0; f < s.frames; ++f) {
            for (int64_t p = 0; p < s.pixels(); ++p)
                if (!moving[static_cast<size_t>(p)])
                    for (int64_t c = 0; c < s.channels; ++c) {
                        const float v = first_pass.at(f, p / s.width, p % s.width, c);
                        if (v > 0 && std::isfinite(v)) level[static_cast<size_t>(f)] += v;
                    }
            mean += level[static_cast<size_t>(f)] / static_cast<double>(s.frames);
        }
        for (double& l : level) {
            if (!(mean > 0) || !(l > 0)) return {};
            l /= mean;
        }
        return level;
    }

    // The moving basis over only the listed pixels, as a compact F x 1 x N sequence.
    std::unique_ptr<Sequence> moving_basis_on(const Sequence& input, const std::vector<int64_t>& pixels,
                                              const Progress& progress) {
        const Shape& s = input.shape();
        if (pixels.empty()) return nullptr;
        Sequence compact(Shape{s.frames, 1, static_cast<int64_t>(pixels.size()), s.channels});
        for (size_t i = 0; i < pixels.size(); ++i)
            for (int64_t f = 0; f < s.frames; ++f)
                for (int64_t c = 0; c < s.channels; ++c)
                    compact.at(f, 0, static_cast<int64_t>(i), c) = input.at(f, pixels[i] / s.width, pixels[i] % s.width, c);
        LowRankStage mb(hybrid_part_options("moving-basis", params()));
        auto out = std::make_unique<Sequence>(compact.shape());
        Results own;
        run_in_memory(mb, compact, *out, Progress([&](double f, const char*) {
            progress.report(0.6 + 0.2 * f, "moving basis");
            return true;
        }), params().get_float("memory_mb") * 1024.0 * 1024.0, own);
        return out;
    }

    // Runs a single-frame filter (e.g. the oidn plugin) on the frames with a non-zero weight and blends
    // it in; returns the share of frames it ran on.
    double blend_single_frame(const std::string& name, const Sequence& input, const std::vector<float>& w_sf,
                              Sequence& output, const Progress& progress) {
        if (find_filter(name).kind != FilterKind::SingleFrame)
            throw Error(Status::InvalidArgument, "single_frame '" + name + "' is not a single-frame filter");
        const Shape& s = input.shape();
        const int64_t P = s.pixels();
        std::vector<int64_t> frames;
        for (int64_t f = 0; f < s.frames; ++f)
            if (std::any_of(w_sf.begin() + f * P, w_sf.begin() + (f + 1) * P, [](float w) { return w > 0; })) frames.push_back(f);
        if (frames.empty()) return 0.0;
        Sequence subset(Shape{static_cast<int64_t>(frames.size()), s.height, s.width, s.channels});
        std::vector<float> buffer(static_cast<size_t>(P * s.channels));
        for (size_t i = 0; i < frames.size(); ++i) {
            input.get_frame(frames[i], buffer.data());
            subset.set_frame(static_cast<int64_t>(i), buffer.data());
            subset.frame_numbers()[i] = input.frame_numbers()[frames[i]];
        }
        subset.channel_names() = input.channel_names();
        auto filter = create_filter(name);
        Sequence filtered(subset.shape());
        filter->execute(subset, filtered, Progress([&](double f, const char* stage) {
            progress.report(0.8 + 0.2 * f, stage);
            return true;
        }));
        for (size_t i = 0; i < frames.size(); ++i)
            for (int64_t p = 0; p < P; ++p) {
                const float w = w_sf[frames[i] * P + p];
                if (w <= 0) continue;
                for (int64_t c = 0; c < s.channels; ++c) {
                    float& o = output.at(frames[i], p / s.width, p % s.width, c);
                    o += w * (filtered.at(static_cast<int64_t>(i), p / s.width, p % s.width, c) - o);
                }
            }
        return static_cast<double>(frames.size()) / static_cast<double>(s.frames);
    }

    // Diffuses each frame's bounding box of pixels with a diffusion weight (plus a halo the diffusion
    // cannot see past) and blends it in; returns the share of pixel-frames diffused.
    double blend_diffusion(const Sequence& input, const std::vector<float>& w_sf, Sequence& output,
                           const Progress& progress) {
        const Shape& s = input.shape();
        const int64_t P = s.pixels();
        const DiffusionOptions options = diffusion_options(params());
        const int64_t halo = options.iterations;
        int64_t touched = 0;
        std::vector<float> crop;
        for (int64_t f = 0; f < s.frames; ++f) {
            progress.report(0.8 + 0.2 * f / s.frames, "diffusion");
            int64_t x0 = s.width, y0 = s.height, x1 = -1, y1 = -1;
            for (int64_t p = 0; p < P; ++p)
                if (w_sf[f * P + p] > 0) {
                    x0 = std::min(x0, p % s.width), x1 = std::max(x1, p % s.width);
                    y0 = std::min(y0, p / s.width), y1 = std::max(y1, p / s.width);
                }
            if (x1 < 0) continue;
            const int64_t cx0 = std::max<int64_t>(0, x0 - halo), cy0 = std::max<int64_t>(0, y0 - halo);
            const int64_t cx1 = std::min(s.width - 1, x1 + halo), cy1 = std::min(s.height - 1, y1 + halo);
            const int64_t cw = cx1 - cx0 + 1, ch = cy1 - cy0 + 1;
            touched += cw * ch;
            crop.resize(static_cast<size_t>(cw * ch * s.channels));
            for (int64_t y = 0; y < ch; ++y)
                for (int64_t x = 0; x < cw; ++x)
                    for (int64_t c = 0; c < s.channels; ++c)
                        crop[(y * cw + x) * s.channels + c] = input.at(f, cy0 + y, cx0 + x, c);
            diffuse_frame(crop.data(), cw, ch, s.channels, options);
            for (int64_t y = y0; y <= y1; ++y)
                for (int64_t x = x0; x <= x1; ++x) {
                    const float w = w_sf[f * P + y * s.width + x];
                    if (w <= 0) continue;
                    for (int64_t c = 0; c < s.channels; ++c) {
                        float& o = output.at(f, y, x, c);
                        o += w * (crop[((y - cy0) * cw + (x - cx0)) * s.channels + c] - o);
                    }
                }
        }
        return static_cast<double>(touched) / static_cast<double>(s.frames * P);
    }
};

}  // namespace

std::unique_ptr<Filter> make_hybrid_filter() { return std::make_unique<HybridFilter>(); }

}  // namespace statfilter
