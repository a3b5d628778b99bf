// The prefilter with its probe, and the temporal result blended back towards it, on a shot in memory
// (statfilter/time_trust.hpp; the streamed form is in the scheduler, frame by frame).
#pragma once
#include "pipeline/frame_stage_pool.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"
#include "statfilter/time_trust.hpp"

namespace statfilter {

// prefiltered = the prefilter on every frame of noisy; trust measures each frame's Stein correction.
void prefilter_and_probe(FrameStagePool& prefilter, const Sequence& noisy, Sequence& prefiltered, TimeTrust& trust,
                         int threads, const ProgressSpan& progress);
// Every frame of result (the temporal filter's output on prefiltered) blended back towards
// prefiltered where noisy does not support the change; returns the mean share kept.
double blend_toward_prefilter(TimeTrust& trust, const Sequence& noisy, const Sequence& prefiltered,
                              Sequence& result, int threads);

}  // namespace statfilter
