// The hybrid with motion compensation (and so the balanced preset) as a stage that streams:
//   1. statistics, over bands of scanlines of every frame: the F x F Gram (shared by alpha and the
//      temporal filter: computed once), then alpha's light fit and energies and the temporal-change
//      test's noise and scores (bands read with the test's 4-row halo);
//   2. nothing moves: global PCA (automatic rank) rebuilt from the same Gram, frame by frame;
//   3. else the temporal filter I_T rebuilt frame by frame, each frame's first pass (I_T with the
//      light diffusion pass) made at once; where I_T ghosts (filters/own_first_pass.hpp: the change
//      test saw motion that alpha did not, or a brief event that I_T misses in this frame), the
//      first pass is the frame's own diffusion instead; both parked on disk with the first pass'
//      statistics (its mean, its light level where nothing moves, the flow images' scale);
//   4. a sliding window of frames t - h .. t + h: frame t's moving pixels averaged along the optical
//      flow (statfilter/aligned_frame.hpp), blended into I_T by the moving weight, handed on.
// Memory: a band, the temporal model and per-pixel maps, then the window's frames; never the shot.
// In memory the same stage runs over the sequence (bands are then the whole frame): one
// implementation, the same numbers either way. The steps are separate calls (analyse_passes;
// first_pass over a range of frames; guides; window over a range of frames), so a plan's tasks can
// make the passes and the guides once and the first passes and the frames in chunks
// (filters/hybrid_analysis_file.hpp): a frame's window reads only frames t - h .. t + h.
#pragma once
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "filters/pass_motion.hpp"
#include "pipeline/low_rank_stage.hpp"
#include "pipeline/stage.hpp"
#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/motion.hpp"
#include "statfilter/motion_compensation.hpp"

namespace statfilter {

struct HybridStageOptions {
    LowRankOptions temporal;      // I_T where nothing moves: the error threshold method or pca
    LowRankOptions still;         // global PCA (automatic rank): the whole answer for a still scene
    GlobalMotionOptions alpha;    // components: the most counted
    bool signal_components = true;  // count only those above the noise threshold
    TemporalChangeOptions change;  // the temporal-change test (z_threshold 0 = off)
    double still_fraction = 0.01;
    int mc_dilate = 4;
    AlignedAverageOptions mc;     // frame_gain and vectors are the stage's
    DiffusionOptions single_frame;  // the frame's own diffusion: the first pass where I_T ghosts
    bool refine_after = false;    // the light diffusion pass on every output frame (the presets')
    // The renderer's passes (StageContext::passes): where they say things move; with passes.surfaces
    // the albedo/normal passes also guide the flow (unless vectors are given, which replace it).
    PassMotionOptions passes;
};

// The typed options of a low-rank part of the hybrid ("pca", "error-threshold": its temporal filter;
// "moving-basis": the study's I_MB) from the hybrid's parameters: the temporal parameters it shares,
// the part's own defaults for the rest.
LowRankOptions hybrid_part_options(const std::string& name, const ParamSet& hybrid_params);
// The typed options of the hybrid filter, from its parameter table (checked there).
// prefiltered: the frames the stage sees are a prefilter's (temporal_change_options).
HybridStageOptions hybrid_stage_options(const ParamSet& hybrid_params, bool prefiltered);
// Whether the hybrid with these parameters streams: motion compensation on and one shared basis. The
// renderer's passes (albedo, normal, vectors) stream beside the input (StageContext::passes).
bool hybrid_streams(const ParamSet& hybrid_params);

// What the window (step 4) needs from the passes before it.
struct HybridAnalysis {
    // A still scene: the frames are global PCA's; the window only hands them on (through the light pass).
    bool still = false;
    std::vector<float> grown;        // per pixel: the moving weight grown by mc_dilate (> 0: averaged)
    std::vector<float> crossings;    // per pixel: where the change test saw motion alpha did not (may be empty)
    std::shared_ptr<const TemporalChange> change;  // the test, for the own first pass (null: off)
    // Per frame: the samples (index in the frame, value) the statistics pass found to be fireflies.
    std::vector<std::vector<std::pair<int64_t, float>>> fireflies;
    // Per frame, from its first pass: its positive sum, its sum over the still pixels, and the pixels
    // given their own diffusion.
    std::vector<double> first_sums, still_levels;
    std::vector<int64_t> own_counts;
    std::vector<double> frame_gain;  // the aligned average's light level of each frame (empty: constant)
    double guide_scale = 0;          // the flow images' scale (the guides' 99.5th percentile)
    // The frames: I_T (the still scene's frames when still), each frame's first pass and its flow
    // guide (not made when still). Parked on scratch by analyse, or read from a plan's files
    // (filters/hybrid_analysis_file.hpp).
    const FrameSource *temporal = nullptr, *first_pass = nullptr, *guides = nullptr;
    std::vector<std::unique_ptr<FrameSource>> held;  // owns the sources above
};

class HybridStage final : public StreamStage, public WindowedStage {
public:
    explicit HybridStage(HybridStageOptions options);
    Footprint footprint() const override;
    double min_bytes(const Shape& shape, int threads) const override;
    // Results as the hybrid's: motion_fraction, the image alpha, beta_source, motion_compensation,
    // aligned_fraction, aligned_frames, own_first_pass_fraction, temporal_rank or temporal_mean_rank,
    // bands.
    void run(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
             Results& results) override;
    // Steps 1-3 in one call (analyse_passes, first_pass over every frame, guides). A still scene's
    // frames go to `still_output` finished (through the light pass); without one they are parked
    // (analysis.temporal) for the window to hand on.
    HybridAnalysis analyse(const FrameSource& source, const StageContext& context, Results& results,
                           const FrameConsumer* still_output) const;
    // Made once the maps are known (the analysis so far; keep: whether the rebuild's threads may keep
    // their buffers), called with each frame of I_T as it is rebuilt, from the rebuild's threads.
    using ModelHook = std::function<std::function<void(int64_t, const float*)>(HybridAnalysis&, bool keep)>;
    // Steps 1 and 2, and I_T parked (analysis.temporal): the passes over the whole shot.
    HybridAnalysis analyse_passes(const FrameSource& source, const StageContext& context, Results& results,
                                  const FrameConsumer* still_output, const ModelHook* each_model = nullptr) const;
    // Step 3 for frames [f0, f1): each frame's first pass, handed to `park`, and its sums (analysis'
    // first_sums, still_levels, own_counts; sized to the shot here). Reads those frames of I_T and
    // the input alone.
    void first_pass(const FrameSource& source, HybridAnalysis& analysis, int64_t f0, int64_t f1,
                    const std::function<void(int64_t, const float*)>& park, const StageContext& context) const;
    // Once every frame's first pass is in (analysis.first_pass and its sums): the light levels of the
    // aligned average, the flow guides (parked: analysis.guides) and their scale.
    void guides(const Shape& shape, HybridAnalysis& analysis, const Sequence& attributes, const StageContext& context,
                Results& results) const;
    // Step 4 for frames [f0, f1): each handed to `consume` once, in any order, from worker threads.
    // Reads frames f0 - h .. f1 - 1 + h of source and of the analysis' frames.
    void window(const FrameSource& source, const HybridAnalysis& analysis, int64_t f0, int64_t f1,
                const FrameConsumer& consume, const StageContext& context, Results& results) const;
    // The least memory the window over frames of this shape needs on one thread (a plan's frame task).
    double window_min_bytes(const Shape& shape) const {
        return window_bytes(shape, 1, false, options_.passes.named_vectors,
                            flow_surfaces(options_.passes.named_vectors, options_.passes.named_surfaces));
    }

    // As a plan's tasks (filters/hybrid_analysis_file.hpp keeps what each hands on).
    const WindowedStage* windowed() const override { return this; }
    int64_t window_half() const override { return options_.mc.half_width; }
    double frames_min_bytes(const Shape& shape) const override { return window_min_bytes(shape); }
    void analyse_into(const FrameSource& source, const std::string& dir, const StageContext& context,
                      Results& results) const override;
    void frame_pass_into(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                         const std::string& dir, const StageContext& context, Results& results) const override;
    void shot_pass_into(const FrameSource& source, const WindowedFiles& files, const std::string& dir,
                        const StageContext& context, Results& results) const override;
    void frames_from(const FrameSource& source, const WindowedFiles& files, int64_t f0, int64_t f1,
                     const FrameConsumer& consume, const StageContext& context, Results& results) const override;

private:
    double analysis_bytes(const Shape& shape) const;
    // keep: the light diffusion pass keeps its working set from frame to frame (when the budget has room).
    // vectors: each window frame holds its vectors; surfaces: the albedo/normal passes the flow runs on.
    double window_bytes(const Shape& shape, int threads, bool keep, bool vectors = false, int surfaces = 0) const;
    double window_bytes(const Shape& shape, int threads, bool keep, const GuideSources& passes) const;
    // The albedo/normal passes the flow runs on: given, used, and no vectors to follow (0 = none).
    int flow_surfaces(bool vectors, int surfaces) const { return options_.passes.surfaces && !vectors ? surfaces : 0; }
    int flow_surfaces(const GuideSources& passes) const {
        return flow_surfaces(passes.vectors != nullptr, (passes.albedo ? 1 : 0) + (passes.normal ? 1 : 0));
    }
    bool flow_on_surfaces(const GuideSources& passes) const { return flow_surfaces(passes) > 0; }
    double first_pass_bytes(const Shape& shape, int threads, bool keep) const;
    double rebuild_bytes(const Shape& shape, int threads, bool keep) const;
    static double maps_bytes(const Shape& shape);
    HybridStageOptions options_;
    ParamSet refine_;  // the light diffusion pass
};

}  // namespace statfilter
