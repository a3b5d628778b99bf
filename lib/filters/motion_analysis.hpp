// The motion maps as the motion and hybrid filters compute them from their parameters.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "filters/pass_motion.hpp"
#include "pipeline/stage.hpp"
#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/motion.hpp"

namespace statfilter {

std::vector<ParamSpec> motion_params();

struct MotionMaps {
    std::shared_ptr<Sequence> alpha;  // 1 frame, 1 channel; 1 = stationary
    std::shared_ptr<Sequence> beta;   // F frames, 1 channel; 1 = moving now
    std::string beta_source;          // "zscore" or "aux"
};

// The renderer's passes a filter is given, each for the input's frames and size: as named inputs
// (sequences the caller holds, or files: "albedo", "normal", "vectors"), or, for albedo and normal,
// as file patterns in the parameters; files are read once here (a run from files streams them
// instead: pipeline/guide_sources.hpp). Resolved (read and checked) before any work, whether
// the scene then needs them or not: a named pass that is missing or does not match is an error.
struct GuidePasses {
    const Sequence* albedo = nullptr;
    const Sequence* normal = nullptr;
    const Sequence* vectors = nullptr;
    std::shared_ptr<const Sequence> read_albedo, read_normal, read_vectors;  // those read from patterns
    bool surfaces() const { return albedo || normal; }
};
GuidePasses guide_passes(const Filter& filter, const Sequence& input, const ParamSet& params);
// Which passes are named (options.named_vectors, named_surfaces), without opening them.
void count_named_passes(const Filter& filter, const ParamSet& params, PassMotionOptions& options);
// The passes as sources (borrowed: the passes must outlive them), for a stage run in memory.
struct GuideMemorySources {
    GuideSources view;
    std::vector<std::unique_ptr<FrameSource>> held;
};
GuideMemorySources guide_memory_sources(const GuidePasses& passes);

// Uses the temporal parameters (transform, nonfinite, shared_basis, memory_mb) and motion_params().
MotionMaps compute_motion(const Sequence& input, const GuidePasses& passes, const ParamSet& params,
                          const ProgressSpan& progress);

// alpha alone (no beta), e.g. to decide whether anything moves at all.
std::shared_ptr<Sequence> compute_alpha(const Sequence& input, const ParamSet& params, const ProgressSpan& progress);

// The two stages, for a caller that already has the series and their basis (the hybrid).
std::shared_ptr<Sequence> compute_alpha(PreparedSeries& series, const TemporalBasis& basis, const ParamSet& params,
                                        const ProgressSpan& progress);
void compute_beta(const Sequence& input, const GuidePasses& passes, const ParamSet& params, MotionMaps& maps);

// The share of each pixel that moves, 1-frame, 1-channel: 1 - alpha, raised to 1 where the temporal-
// change test (change_z > 0), the albedo/normal passes (beta from them, in any frame) or the
// renderer's motion vectors (when given) say the pixel moves. The
// still/moving decisions of the hybrid and of auto and the hybrid's motion-compensated region use it.
// crossings, when given, receives crossing_weight (empty when the test is off); change, when given,
// the change test itself (null when it is off), for the own first pass (filters/own_first_pass.hpp).
std::shared_ptr<Sequence> moving_weight(const Sequence& input, const Sequence& alpha, const GuidePasses& passes,
                                        const ParamSet& params, std::vector<float>* crossings = nullptr,
                                        std::unique_ptr<TemporalChange>* change = nullptr);

// The temporal-change test's options from a filter's parameters. Its map is not grown (grow_z 0)
// on frames a prefilter made: a denoiser's residual is spatially correlated, so the blotches it leaves
// pass the lower threshold where render noise does not (measured after OIDN: still-scene jitter
// 13% higher, relMSE no lower). prefiltered: the frames the test sees are a prefilter's.
TemporalChangeOptions temporal_change_options(const ParamSet& params, bool prefiltered);

// Per pixel, the temporal-change map times alpha: motion alpha missed (an object crossing the pixel
// in a frame or two, which no temporal basis follows), where the hybrid's first pass is the frame's
// own diffusion (filters/hybrid_stage.hpp). The pixels with a weight above 0, in order.
std::vector<float> crossing_weight(const Sequence& change, const Sequence& alpha);
std::vector<int64_t> crossing_pixels(const std::vector<float>& weight);

// A renderer pass (albedo, normal, vectors: `name`) for the input's frames, read from a file pattern
// or a layer of the input's files (pipeline/guide_sources.hpp pass_files); its frames and size must
// match the input's.
std::unique_ptr<Sequence> read_pass(const Sequence& input, const std::string& name, const std::string& pattern);

}  // namespace statfilter
