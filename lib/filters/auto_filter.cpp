// Picks the method for the scene at the quality the user asks for (docs/benchmarks.md, "Presets",
// has the map these choices come from):
//   fast     - global temporal PCA (automatic rank) on the raw values: the cheapest filter that
//              removes most of the noise (the log transform costs more than the PCA at this rank);
//              it ghosts where things move.
//   balanced - measures how much of the frame moves (alpha) and runs the filter the benchmark found
//              most accurate for its cost on such a scene, then the diffusion postfilter:
//                (almost) nothing moves: global PCA, the cheapest and the best on a still camera
//                with changing light (cornell_light);
//                something moves: the hybrid with motion compensation at its fast settings (DIS
//                ultrafast flow, 4 frames a side, on its first pass, or on the albedo/normal passes
//                when given): per-pixel ranks where still, frames aligned along the flow where
//                things move. On camera
//                motion it lowered relMSE ~35% against the error threshold method, on local motion
//                5-10%, at ~2.5x its time (docs/methods.md, "Motion compensation").
//   high     - the hybrid at its default (more accurate) flow, or global PCA on a still scene, then
//              Intel Open Image Denoise on its result when its plugin can run here, blended back towards
//              OIDN on the noisy frames where they do not support the temporal change (prefilter_order
//              last: OIDN then sees frames already averaged over time); without OIDN, the hybrid
//              wherever something moves, with the albedo/normal passes when given.
// A postfilter the user names on this filter replaces the preset's (Filter::execute runs it), and
// `transform` other than `preset` replaces the preset's transform.
// It says what it picked and why (results "method" and "reason").
#include <cstdio>
#include <mutex>
#include <utility>
#include <vector>

#include "filters/builtin_filters.hpp"
#include "filters/frame_stages.hpp"
#include "filters/hybrid_analysis_file.hpp"
#include "filters/hybrid_stage.hpp"
#include "filters/motion_analysis.hpp"
#include "filters/temporal_params.hpp"
#include "pipeline/light_levels.hpp"
#include "pipeline/low_rank_stage.hpp"
#include "pipeline/noise_probe.hpp"
#include "pipeline/parallel.hpp"
#include "pipeline/trusted_prefilter.hpp"
#include "statfilter/filter_registry.hpp"

namespace statfilter {
namespace {

// Why OIDN cannot run here, or empty when it can.
std::string oidn_problem() {
    for (const FilterEntry* entry : all_filters())
        if (entry->name == "oidn") return entry->available() ? "" : entry->problem;
    return "the oidn plugin is not installed";
}

// What a preset runs, [prefilter then] method [then the diffusion postfilter], and why.
struct Choice {
    std::string method, prefilter, reason;
    bool refine = false;
    bool passes = false;  // hand the albedo/normal passes to the method
    std::vector<std::pair<std::string, std::string>> params;  // set on the method
};

// quality balanced or high, once alpha has measured the share of moving pixels.
Choice choose(const std::string& quality, double moving, bool still, bool passes, bool oidn,
              const std::string& oidn_note) {
    char share[32];
    std::snprintf(share, sizeof share, "%.1f%%", 100 * moving);
    const std::string prefix = "quality " + quality + ": " + share + " of pixels move";
    Choice c;
    if (quality == "high" && oidn) {
        // The temporal filter on the noisy frames, then OIDN on its result, blended back towards OIDN
        // on the noisy frames where they do not support the change (prefilter_order=last).
        c.prefilter = "oidn";
        c.method = still ? "pca" : "hybrid";
        c.reason = prefix + (still ? ": global PCA (a still scene)" : ": the hybrid, frames aligned along the flow where things move") +
                   ", then OIDN on its result, kept where the noisy frames support it";
    } else if (quality == "high" && !still) {
        c.method = "hybrid";
        c.refine = true;  // the hybrid's own default
        c.passes = passes;
        c.reason = prefix + (passes ? " and albedo/normal passes are given: the hybrid uses them"
                                    : ": the hybrid (no albedo/normal passes given)");
    } else if (still) {
        c.method = "pca";
        c.refine = true;
        c.reason = prefix + ": a still scene, where global PCA is cheapest and most accurate; then a light diffusion pass";
    } else {
        c.method = "hybrid";
        c.refine = true;
        c.passes = passes;
        c.params = {{"mc_flow", "ultrafast"}, {"mc_half_width", "4"}};
        c.reason = prefix + ": the hybrid, per-pixel ranks where still and frames aligned along a fast optical flow " +
                   (passes ? "on the albedo/normal passes " : "") + "where things move; then a light diffusion pass";
    }
    c.reason += oidn_note;
    return c;
}

// Results "noise_in_time" (the ratio, when measured) and "warning" (when the noise is the same in
// every frame: the front ends show it whatever their verbosity).
void report_noise_in_time(const NoiseInTime& noise, Results& results) {
    if (noise.pairs > 0) results.set("noise_in_time", noise.ratio());
    const std::string warning = same_noise_warning(noise);
    if (!warning.empty()) results.set("warning", warning);
}

// Results "light_swing" (the smoothed light level's largest departure from the shot's mean light)
// and "light_levels": whether the levels were divided out, and why.
void report_light_levels(const LightLevels& light, Results& results) {
    results.set("light_swing", light.swing);
    char text[200];
    if (light.modelled)
        std::snprintf(text, sizeof text, "divided out: the light swings %.2f%% over the shot (frame-to-frame spread "
                      "%.2f%%), followed over +-%d frames", 100 * light.swing, 100 * light.noise, light.half_width);
    else
        std::snprintf(text, sizeof text, "still: the light swings %.2f%% over the shot (frame-to-frame spread %.2f%%)",
                      100 * light.swing, 100 * light.noise);
    results.set("light_levels", text);
}

// The results of a preset that runs OIDN alone because the noise is the same in every frame.
void report_oidn_alone(const std::string& quality, const std::string& transform, const NoiseInTime& noise,
                       Results& results) {
    results.set("method", "oidn");
    results.set("reason", "quality " + quality + ": the noise is the same in every frame, which no temporal "
                          "filter removes: OIDN alone on each frame");
    results.set("quality", quality);
    results.set("transform", transform);
    report_noise_in_time(noise, results);
}

// The noise-in-time check on the frames a preset's stage is given: the shot as rendered, unless a
// prefilter ran first (its frames say nothing of the renderer's seed): then not measured.
NoiseInTime probe_shot(bool noisy_frames, const FrameSource& source) {
    return noisy_frames ? probe_noise_in_time(source) : NoiseInTime{};
}

Choice fast_choice() {
    Choice c;
    c.method = "pca";
    c.reason = "quality fast: global PCA, the cheapest filter; it may ghost where things move";
    return c;
}

// The streamed form of a preset: the stage, then what the preset picked and why, as auto reports it.
class AnnotatedStage final : public StreamStage {
public:
    AnnotatedStage(std::unique_ptr<StreamStage> inner, Choice choice, std::string transform, bool noisy_frames)
        : inner_(std::move(inner)), choice_(std::move(choice)), transform_(std::move(transform)),
          noisy_frames_(noisy_frames) {}
    Footprint footprint() const override { return inner_->footprint(); }
    double min_bytes(const Shape& shape, int threads) const override { return inner_->min_bytes(shape, threads); }
    void run(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
             Results& results) override {
        noise_ = probe_shot(noisy_frames_, source);  // a few rows of six frames, before the work
        annotate(results);  // known before the first frame, so the frames can say what made them
        Results own;
        inner_->run(source, consume, context, own);
        add_stage_results(choice_.method, own, results);
    }

    const StreamStage& core() const override { return *inner_; }
    void annotate(Results& results) const override {
        results.set("method", choice_.method);
        results.set("reason", choice_.reason);
        results.set("quality", "fast");
        results.set("transform", transform_);
        report_noise_in_time(noise_, results);
    }

private:
    std::unique_ptr<StreamStage> inner_;
    Choice choice_;
    std::string transform_;
    bool noisy_frames_;
    NoiseInTime noise_;
};

// balanced and high streamed: the hybrid's stage decides still or moving once, from one analysis, and
// the preset's choice and reason are reported from what it found.
class MotionPresetStage final : public StreamStage, public WindowedStage {
public:
    // oidn: the pipeline runs OIDN around the stage (quality high; Filter::frame_stage_params);
    // oidn_note: why high does not (appended to the reason).
    MotionPresetStage(HybridStageOptions options, std::string quality, std::string transform, double still_fraction,
                      bool oidn, bool noisy_frames, bool light_levels, std::string oidn_note)
        : refine_(options.refine_after), oidn_(oidn), noisy_frames_(noisy_frames), light_levels_(light_levels),
          surfaces_(options.passes.surfaces), half_width_(options.mc.half_width), stage_(std::move(options)),
          quality_(std::move(quality)), transform_(std::move(transform)), oidn_note_(std::move(oidn_note)),
          still_fraction_(still_fraction) {}
    Footprint footprint() const override { return stage_.footprint(); }
    double min_bytes(const Shape& shape, int threads) const override { return stage_.min_bytes(shape, threads); }
    void run(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
             Results& results) override {
        Results own;
        const NoiseInTime noise = probe_shot(noisy_frames_, source);  // a few rows of six frames, before the work
        if (oidn_ && noise.ratio() < kSameNoiseRatio) {
            pass_frames_to_oidn(source, consume, context, noise, results);
            return;
        }
        // The choice is made once the statistics are in, before the first frame: reported then, so
        // the frames can say what made them.
        std::once_flag decided;
        bool still = false;
        const bool passes = surfaces_ && (context.passes.albedo || context.passes.normal);
        const auto report = [&] { still = report_choice(own, noise, results, passes); };
        // A light that changes over the shot is divided out before the stage and multiplied back
        // after (pipeline/light_levels.hpp); a still light leaves the stage its source untouched.
        // Not with a prefilter around the stage (high's OIDN): there it was mixed (cornell_light 4 spp
        // 9% lower relMSE, but more still-scene jitter and a worse moving region; docs/methods.md).
        LightLevels light;
        if (light_levels_) light = measure_light_levels(source, context.threads);
        const LevelledSource levelled(source, light);
        stage_.run(light.modelled ? static_cast<const FrameSource&>(levelled) : source, [&](int64_t f, float* pixels) {
            std::call_once(decided, report);
            if (light.modelled) levelled.restore(f, pixels);
            consume(f, pixels);
        }, context, own);
        std::call_once(decided, report);  // a shot of no frames
        if (light_levels_) report_light_levels(light, results);
        add_hybrid_results(own, still, results);
    }

    // A plan's tasks (balanced without OIDN): the hybrid's phases, each on the shot at one light level.
    const WindowedStage* windowed() const override { return oidn_ ? nullptr : this; }
    int64_t window_half() const override { return half_width_; }
    double frames_min_bytes(const Shape& shape) const override { return stage_.window_min_bytes(shape); }

    void analyse_into(const FrameSource& source, const std::string& dir, const StageContext& context,
                      Results& results) const override {
        Results own;
        const NoiseInTime noise = probe_shot(noisy_frames_, source);
        LightLevels light;
        if (light_levels_) light = measure_light_levels(source, context.threads);
        const LevelledSource levelled(source, light);
        const HybridAnalysis analysis =
            stage_.analyse_passes(light.modelled ? static_cast<const FrameSource&>(levelled) : source, context, own, nullptr);
        const bool still = report_choice(own, noise, results);
        if (light_levels_) report_light_levels(light, results);
        add_hybrid_results(own, still, results);
        std::string levels, channels;
        for (double l : light.levels) levels += (levels.empty() ? "" : ", ") + json_number(l);
        for (uint8_t c : light.channels) channels += std::string(channels.empty() ? "" : ", ") + (c ? "1" : "0");
        save_hybrid_passes(analysis, source.shape(), dir,
                           "\"method\": " + json_quote(results.get_string("method")) + ",\n  \"reason\": " +
                               json_quote(results.get_string("reason")) + ",\n  \"light_modelled\": " +
                               (light.modelled ? "true" : "false") + ",\n  \"light_levels\": [" + levels +
                               "],\n  \"light_channels\": [" + channels + "]");
    }

    void frame_pass_into(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                         const std::string& dir, const StageContext& context, Results& results) const override {
        const LightLevels light = saved_light(files, results);
        const LevelledSource levelled(source, light);
        stage_.frame_pass_into(light.modelled ? static_cast<const FrameSource&>(levelled) : source, files, f0, f1, dir,
                               context, results);
    }

    void shot_pass_into(const FrameSource& source, const WindowedFiles& files, const std::string& dir,
                        const StageContext& context, Results& results) const override {
        const LightLevels light = saved_light(files, results);
        const LevelledSource levelled(source, light);
        Results own;
        stage_.shot_pass_into(light.modelled ? static_cast<const FrameSource&>(levelled) : source, files, dir, context, own);
        add_hybrid_results(own, false, results);
    }

    void frames_from(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                     const FrameConsumer& consume, const StageContext& context, Results& results) const override {
        const LightLevels light = saved_light(files, results);
        const LevelledSource levelled(source, light);
        Results own;
        stage_.frames_from(light.modelled ? static_cast<const FrameSource&>(levelled) : source, files, f0, f1,
                           [&](int64_t f, float* pixels) {
                               if (light.modelled) levelled.restore(f, pixels);
                               consume(f, pixels);
                           },
                           context, own);
        add_hybrid_results(own, false, results);
    }

private:
    // The light levels the analysis measured, and its choice (results: "method", "reason").
    static LightLevels saved_light(const WindowedFiles& files, Results& results) {
        const JsonValue json = hybrid_passes_json(files.analysis);
        for (const char* key : {"method", "reason", "light_modelled", "light_levels", "light_channels"})
            if (!json.find(key)) throw Error(Status::InvalidArgument, "'" + files.analysis + "/analysis.json' has no '" + key + "'");
        LightLevels light;
        light.modelled = json.find("light_modelled")->boolean();
        for (const JsonValue& v : json.find("light_levels")->array()) light.levels.push_back(v.number());
        for (const JsonValue& v : json.find("light_channels")->array()) light.channels.push_back(v.number() != 0 ? 1 : 0);
        results.set("method", json.find("method")->string());
        results.set("reason", json.find("reason")->string());
        return light;
    }

    // What the preset picked, from the motion the analysis measured; returns whether the scene is still.
    // passes: the albedo/normal passes are given and used (balanced, and high without OIDN).
    bool report_choice(const Results& own, const NoiseInTime& noise, Results& results, bool passes = false) const {
        const double moving = own.get_float("motion_fraction");
        const bool still = moving < still_fraction_;
        const Choice choice = choose(quality_, moving, still, passes, oidn_, oidn_note_);
        std::string picked = choice.method;
        if (refine_) picked += std::string(" then ") + kRefinePostfilter;
        if (oidn_) picked += " then oidn";
        results.set("motion_fraction", moving);
        results.set("method", picked);
        results.set("reason", choice.reason);
        results.set("quality", quality_);
        results.set("transform", transform_);
        report_noise_in_time(noise, results);
        return still;
    }

    static void add_hybrid_results(const Results& own, bool still, Results& results) {
        for (const auto& name : own.names()) {
            if (name == "alpha" || name == kMotionPathResult) continue;
            // The still scene's global PCA reports its rank as pca's.
            if (still && name == "temporal_rank") results.copy(own, name, "pca.rank");
            else if (!still) results.copy(own, name, "hybrid." + name);
        }
        if (own.has("alpha")) results.copy(own, "alpha", "alpha");
        if (own.has(kMotionPathResult)) results.copy(own, kMotionPathResult, kMotionPathResult);
        if (own.has("bands")) results.copy(own, "bands", "bands");
    }

    // Noise that is the same in every frame: no temporal model removes it, and aligning frames along a
    // flow that the fixed pattern holds still smears the picture (camera_pan, one seed: 2.1x OIDN's
    // relMSE with the hybrid first). The frames pass through unchanged, so OIDN, which runs on what the
    // stage hands on, denoises each alone (and the trust blend, comparing it with itself, keeps it).
    void pass_frames_to_oidn(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
                             const NoiseInTime& noise, Results& results) const {
        report_oidn_alone(quality_, transform_, noise, results);
        const Shape& s = source.shape();
        const Progress none;
        parallel_for(s.frames, context.threads, [&](int64_t f) {
            std::vector<float> frame(static_cast<size_t>(s.pixels() * s.channels));
            source.read_rows(f, 0, s.height, frame.data());
            consume(f, frame.data());
        }, {context.progress ? *context.progress : none, 0, 1, "frames"});
    }

    bool refine_, oidn_, noisy_frames_, light_levels_, surfaces_;
    int64_t half_width_;
    HybridStage stage_;
    std::string quality_, transform_, oidn_note_;
    double still_fraction_;
};

class AutoFilter final : public Filter {
public:
    AutoFilter() : Filter(make_params()) {
        for (const char* pass : {"albedo", "normal", "vectors"}) accept_input(pass);
        declare_image_result("alpha");
    }

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {
            choice_param("quality", "balanced", {"fast", "balanced", "high"},
                         "fast: global PCA; balanced: the method measured best for the scene's motion; high: "
                         "the hybrid at its most accurate flow, then OIDN on its result (when available)"),
            float_param("still_fraction", "0.01", 0, 1,
                        "below this share of moving pixels (the mean moving weight: 1 - alpha, raised by the "
                        "temporal-change test and the motion vectors) the scene counts as still"),
        };
        for (auto& c : motion_params()) p.push_back(c);
        for (auto& c : temporal_common_params()) {
            if (c.name == "transform") {  // the preset picks it unless the user does
                c.default_value = "preset";
                c.choices.insert(c.choices.begin(), "preset");
                c.description = "preset: the quality's (fast: none, else log); or as the temporal filters: " +
                                c.description;
            }
            if (c.name == "prefilter_order") c.default_value = kHybridPrefilterOrder;  // the hybrid's, which it runs
            p.push_back(c);
        }
        return p;
    }

    // quality fast needs no analysis: it is global PCA, which streams. balanced and high are the
    // hybrid's stage (it measures the motion in its statistics passes), which streams, the renderer's
    // passes beside its input; high's OIDN runs around it frame by frame, as a prefilter run last
    // (frame_stage_params; docs/architecture.md, "What streams").
    std::unique_ptr<StreamStage> stream_stage() const override {
        const std::string quality = params().get_string("quality");
        if (quality != "fast") {
            const ParamSet hybrid = hybrid_params();
            if (!hybrid_streams(hybrid)) return nullptr;
            // A prefilter the user names, or high's OIDN, runs around the preset's stage (Filter::execute).
            const ParamSet stages = frame_stage_params();
            HybridStageOptions options = hybrid_stage_options(hybrid, temporal_sees_prefilter(stages));
            // else Filter::execute runs the user's postfilter, or the prefilter in its place
            options.refine_after = params().get_string("postfilter").empty() && !prefilter_runs_last(stages);
            // The albedo/normal passes guide the hybrid without OIDN (balanced, and high when OIDN cannot
            // run): the flow runs on them and they say where things move. high with OIDN follows the
            // vectors only.
            options.passes.surfaces = !picks_oidn();
            count_named_passes(*this, params(), options.passes);
            // high without OIDN says why (OIDN only when the user named no prefilter of their own).
            const std::string problem =
                quality == "high" && params().get_string("prefilter").empty() ? oidn_problem() : "";
            return std::make_unique<MotionPresetStage>(std::move(options), quality, resolved_transform(),
                                                       params().get_float("still_fraction"), picks_oidn(),
                                                       !temporal_sees_prefilter(stages),
                                                       stages.get_string("prefilter").empty(),
                                                       problem.empty() ? "" : " (OIDN not used: " + problem + ")");
        }
        ParamSet pca = create_filter("pca")->params();
        for (const char* name : {"nonfinite", "shared_basis", "memory_mb"}) pca.set_string(name, params().get_string(name));
        pca.set_string("transform", fast_transform());
        return std::make_unique<AnnotatedStage>(std::make_unique<LowRankStage>(low_rank_options(pca, LowRankModel::Global)), fast_choice(),
                                                fast_transform(), !temporal_sees_prefilter(frame_stage_params()));
    }
    // quality high where OIDN can run and the preset streams: OIDN as a prefilter (at its defaults, run
    // last), which Filter::execute and the scheduler run around the stage frame by frame.
    ParamSet frame_stage_params() const override {
        ParamSet p = params();
        if (picks_oidn()) p.set_string("prefilter", "oidn");
        return p;
    }
    // In memory (motion_compensation=off or shared_basis=0): what the hybrid holds, and the shot divided by its light level.
    double resident_copies() const override { return stream_stage() ? 2 : 5; }
    Footprint footprint() const override {
        auto stage = stream_stage();
        return stage ? stage->footprint() : Footprint{};
    }

private:
    // quality high, no prefilter of the user's, OIDN can run here, and the preset's stage streams
    // (else run() picks OIDN itself on the shot in memory).
    bool picks_oidn() const {
        return params().get_string("quality") == "high" && params().get_string("prefilter").empty() &&
               oidn_problem().empty() && hybrid_streams(hybrid_params());
    }

    // The preset's transform: fast's, or log, unless the user named one.
    std::string resolved_transform() const {
        const std::string& t = params().get_string("transform");
        if (t != "preset") return t;
        return params().get_string("quality") == "fast" ? fast_transform() : "log";
    }

    // The hybrid's parameters as balanced or high (without OIDN) runs it: its defaults, the user's
    // temporal and motion parameters (the albedo/normal passes among them), the preset's settings.
    ParamSet hybrid_params() const {
        ParamSet p = create_filter("hybrid")->params();
        const std::string quality = params().get_string("quality");
        for (const char* name : {"transform_scale", "firefly_z", "keep_mean", "nonfinite", "shared_basis", "memory_mb", "still_fraction"})
            p.set_string(name, params().get_string(name));
        p.set_string("transform", resolved_transform());
        for (const auto& spec : motion_params()) p.set_string(spec.name, params().get_string(spec.name));
        if (quality == "balanced") {
            p.set_string("mc_flow", "ultrafast");
            p.set_string("mc_half_width", "4");
        }
        return p;
    }

    // The transform of quality fast: none (raw values measured best for global PCA), unless named.
    std::string fast_transform() const {
        const std::string& t = params().get_string("transform");
        return t == "preset" ? "none" : t;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        const std::string quality = params().get_string("quality");
        // The renderer's passes, read and checked before any work, used or not.
        const GuidePasses guides = guide_passes(*this, input, params());
        if (quality != "fast")
            if (auto stage = stream_stage()) {
                const GuideMemorySources sources = guide_memory_sources(guides);
                run_in_memory(*stage, input, output, progress, params().get_float("memory_mb") * 1024.0 * 1024.0,
                              mutable_results(), sources.view);
                return;
            }
        Choice choice;
        std::shared_ptr<Sequence> alpha;
        const NoiseInTime noise = probe_shot(!temporal_sees_prefilter(frame_stage_params()), *memory_source(input));
        // The transform: the preset's unless the user named one.
        std::string transform = params().get_string("transform");
        if (transform == "preset") transform = quality == "fast" ? fast_transform() : "log";
        ParamSet resolved = params();
        resolved.set_string("transform", transform);
        if (quality == "fast") {
            choice = fast_choice();
        } else {
            // OIDN only when the user has not named a prefilter of their own (Filter::execute ran it).
            const bool want_oidn = quality == "high" && params().get_string("prefilter").empty();
            const std::string problem = want_oidn ? oidn_problem() : "";
            const std::string oidn_note = problem.empty() ? "" : " (OIDN not used: " + problem + ")";
            if (want_oidn && problem.empty() && noise.ratio() < kSameNoiseRatio) {
                // As the streamed preset: no temporal model removes noise that is the same in every frame.
                auto oidn = create_filter("oidn");
                oidn->execute(input, output, progress);
                if (params().get_int("keep_mean") != 0) keep_prefilter_light(input, output, resolve_threads(0));
                report_oidn_alone(quality, transform, noise, mutable_results());
                add_stage_results("oidn", oidn->results(), mutable_results());
                return;
            }
            // alpha, the temporal-change test and the vectors (when given) decide; beta (z-scores or
            // passes) is left to the hybrid if it is picked.
            alpha = compute_alpha(input, resolved, {progress, 0.0, 0.3, "analyse"});
            const double moving = mean_of_map(*moving_weight(input, *alpha, guides, resolved));
            mutable_results().set("motion_fraction", moving);
            const bool passes = guides.surfaces();
            choice = choose(quality, moving, moving < params().get_float("still_fraction"), passes,
                            want_oidn && problem.empty(), oidn_note);
        }
        auto chosen = create_filter(choice.method);
        for (const char* name : {"transform", "nonfinite", "shared_basis", "memory_mb", "prefilter_trust", "prefilter_order",
                                 "prefilter_trust_tile", "prefilter_trust_pool", "prefilter_trust_pool_still", "prefilter_trust_probe", "prefilter_trust_stein",
                                 "keep_mean"})
            chosen->params().set_string(name, resolved.get_string(name));
        if (choice.method == "hybrid")
            for (const auto& spec : motion_params())
                if (spec.name != "albedo" && spec.name != "normal")
                    chosen->params().set_string(spec.name, params().get_string(spec.name));
        for (const auto& [name, value] : choice.params) chosen->params().set_string(name, value);
        if (choice.method == "hybrid") {  // the passes as read once here
            chosen->set_input("vectors", guides.vectors);
            chosen->set_input("albedo", choice.passes ? guides.albedo : nullptr);
            chosen->set_input("normal", choice.passes ? guides.normal : nullptr);
        }
        if (!choice.prefilter.empty()) chosen->params().set_string("prefilter", choice.prefilter);
        // The postfilter: the preset's, unless the user named one on this filter, which
        // Filter::execute runs after this one instead.
        const bool refine = choice.refine && params().get_string("postfilter").empty();
        chosen->params().set_string("postfilter", refine ? kRefinePostfilter : "");
        chosen->params().set_string("postfilter_params", refine ? kRefinePostfilterParams : "");
        // As the streamed preset: a light that changes over the shot is divided out before the method
        // and multiplied back after, unless a prefilter runs around it (high's OIDN, the user's).
        const bool levels_apply = quality != "fast" && choice.prefilter.empty() && params().get_string("prefilter").empty();
        const auto source = memory_source(input);
        const LightLevels light = levels_apply ? measure_light_levels(*source, resolve_threads(0)) : LightLevels{};
        const LevelledSource levelled(*source, light);
        const Progress quiet;
        std::unique_ptr<Sequence> levelled_input;
        if (light.modelled) {
            levelled_input = std::make_unique<Sequence>(input.shape());
            levelled_input->copy_attributes_from(input);
            parallel_for(input.shape().frames, resolve_threads(0), [&](int64_t f) {
                std::vector<float> frame(static_cast<size_t>(input.shape().pixels() * input.shape().channels));
                levelled.read_rows(f, 0, input.shape().height, frame.data());
                levelled_input->set_frame(f, frame.data());
            }, {quiet, 0, 1, "light"});
        }
        const double start = alpha ? 0.3 : 0.0;
        chosen->execute(levelled_input ? *levelled_input : input, output, Progress([&](double f, const char* stage) {
            progress.report(start + (1 - start) * f, stage);
            return true;
        }));
        if (light.modelled)
            parallel_for(output.shape().frames, resolve_threads(0), [&](int64_t f) {
                std::vector<float> frame(static_cast<size_t>(output.shape().pixels() * output.shape().channels));
                output.get_frame(f, frame.data());
                levelled.restore(f, frame.data());
                output.set_frame(f, frame.data());
            }, {quiet, 0, 1, "light"});
        if (levels_apply) report_light_levels(light, mutable_results());
        std::string picked = choice.method;
        if (!choice.prefilter.empty())
            picked = prefilter_runs_last(chosen->params()) ? choice.method + " then " + choice.prefilter
                                                           : choice.prefilter + " then " + choice.method;
        if (refine) picked += std::string(" then ") + kRefinePostfilter;
        mutable_results().set("method", picked);
        mutable_results().set("reason", choice.reason);
        report_noise_in_time(noise, mutable_results());
        mutable_results().set("quality", quality);
        mutable_results().set("transform", transform);
        for (const auto& name : chosen->results().names())
            if (name != "alpha" && name != "beta" && name != "rank_map")
                mutable_results().set(choice.method + "." + name, chosen->results().get_string(name));
        if (alpha) mutable_results().set_image("alpha", alpha);
    }
};

}  // namespace

std::unique_ptr<Filter> make_auto_filter() { return std::make_unique<AutoFilter>(); }

}  // namespace statfilter
