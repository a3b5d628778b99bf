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
// implementation, the same numbers either way.
#pragma once
#include <memory>

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
};

// The typed options of the hybrid filter, from its parameter table (checked there).
// prefiltered: the frames the stage sees are a prefilter's (temporal_change_options).
HybridStageOptions hybrid_stage_options(const ParamSet& hybrid_params, bool prefiltered);
// Whether the hybrid with these parameters streams: motion compensation on, one shared basis, and no
// renderer pass (albedo, normal, vectors) to read alongside, which still run in memory.
bool hybrid_streams(const ParamSet& hybrid_params, bool names_passes);

class HybridStage final : public StreamStage {
public:
    explicit HybridStage(HybridStageOptions options);
    Footprint footprint() const override;
    double min_bytes(const Shape& shape, int threads) const override;
    // Results as the hybrid's: motion_fraction, the image alpha, beta_source, motion_compensation,
    // aligned_fraction, aligned_frames, own_first_pass_fraction, temporal_rank or temporal_mean_rank,
    // bands.
    void run(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
             Results& results) override;

private:
    double analysis_bytes(const Shape& shape) const;
    // keep: the light diffusion pass keeps its working set from frame to frame (when the budget has room).
    double window_bytes(const Shape& shape, int threads, bool keep) const;
    double first_pass_bytes(const Shape& shape, int threads, bool keep) const;
    double rebuild_bytes(const Shape& shape, int threads, bool keep) const;
    static double maps_bytes(const Shape& shape);
    HybridStageOptions options_;
    ParamSet refine_;  // the light diffusion pass
};

}  // namespace statfilter
