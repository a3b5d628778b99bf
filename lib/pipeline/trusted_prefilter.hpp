// The prefilter with its probe, and the temporal result blended back towards it, on a shot in memory
// (statfilter/time_trust.hpp; the streamed form is in the scheduler, frame by frame).
#pragma once
#include <memory>
#include <vector>

#include "pipeline/frame_source.hpp"
#include "pipeline/frame_stage_pool.hpp"
#include "pipeline/stage.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"
#include "statfilter/time_trust.hpp"

namespace statfilter {

// prefiltered = the prefilter on every frame of noisy; trust measures each frame's Stein correction.
void prefilter_and_probe(FrameStagePool& prefilter, const Sequence& noisy, Sequence& prefiltered, TimeTrust& trust,
                         int threads, const ProgressSpan& progress);
// The single-frame filter on every frame of frames, in place (a prefilter run last); attributes: the
// shot's frame numbers and channel names. With keep_light the result is scaled back to the light
// frames had (light_gain of their sums before and after): a single-frame denoiser does not keep it,
// least of all where it has little to see (a one-row crop lost 12% of its light to OIDN).
// Returns the gain applied (empty without keep_light).
std::vector<float> filter_frames(FrameStagePool& filter, Sequence& frames, const Sequence& attributes, int threads,
                                 const ProgressSpan& progress, bool keep_light);
// Every frame of result (the temporal filter's output on prefiltered) blended back towards
// prefiltered where noisy does not support the change; returns the mean share kept.
// A single-frame denoiser does not keep the light (OIDN brightens 4-spp frames by ~0.9%); the noisy
// render is unbiased, so the prefiltered shot is scaled to its light, channel by channel: gain[c] =
// sum of noisy / sum of prefiltered over every frame (1 where either sum is not positive). sums:
// [frame][channel], added in frame order so the gain does not depend on threads.
std::vector<float> light_gain(const std::vector<std::vector<double>>& noisy, const std::vector<std::vector<double>>& prefiltered);
// Each channel's sum over one contiguous frame (finite samples).
std::vector<double> channel_sums(const float* frame, const Shape& shape);
// The same on a shot in memory: prefiltered scaled in place.
void keep_prefilter_light(const Sequence& noisy, Sequence& prefiltered, int threads);
// Channel c of every frame times gain[c], in place.
void scale_channels(Sequence& frames, const std::vector<float>& gain, int threads);
// The same on one contiguous frame of `shape` (one frame).
void scale_channels(float* frame, const Shape& shape, const std::vector<float>& gain);

double blend_toward_prefilter(TimeTrust& trust, const Sequence& noisy, const Sequence& prefiltered,
                              Sequence& result, int threads);
// The noisy frames as the trust blend's probe saw them (TimeTrust::perturb_rows), read through source:
// the temporal filter's second run, for its own Stein term. Every frame must have been probed.
std::unique_ptr<FrameSource> probed_source(const FrameSource& source, const TimeTrust& trust);
// TimeTrust::probe_temporal on every frame of a shot in memory: result = P(T(noisy)), probed_result
// = P(T(probe)), both scaled alike.
void probe_temporal_result(TimeTrust& trust, const Sequence& noisy, const Sequence& prefiltered, const Sequence& result,
                           const Sequence& probed_result, int threads);

// Hands trust the stage's motion path when its results have one (kMotionPathResult: where the fit
// pools over still_pool frames, and where the temporal probe counts), and says whether the temporal
// result's probe runs after the stage's run: everywhere (prefilter_trust_stein=both), where the stage
// followed the motion (moving), false for moving when nothing moved (a still scene, a stage that
// models the whole shot: the second run would add nothing) and with no temporal probe.
bool prepare_temporal_probe(TimeTrust& trust, const TimeTrustOptions& options, const Results& results);

}  // namespace statfilter
