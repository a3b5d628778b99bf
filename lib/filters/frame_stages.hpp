// The single-frame stages of the temporal filters. A prefilter (the oidn plugin, diffusion, any
// single-frame plugin) runs on every frame first and the temporal filter works on its output, which
// removes the flicker a single-frame denoiser leaves. A postfilter runs on every frame of the
// temporal filter's output: what a temporal basis leaves is spatially white noise on a smooth
// signal (indirect light before the albedo), which a few steps of edge-stopping diffusion remove
// (docs/methods.md, "Postfilter"). Filter::execute runs both for any filter whose parameters
// include them, so no filter repeats them.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "statfilter/filter.hpp"
#include "statfilter/params.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"
#include "statfilter/time_trust.hpp"

namespace statfilter {

// The postfilter the hybrid and the balanced preset use: three steps of diffusion with K = 3x the
// frame's gradient noise lowered relMSE on every scene and level measured (geometric mean 0.69x
// after pca and error-threshold, never above 0.95x; docs/methods.md, "Postfilter").
inline constexpr const char* kRefinePostfilter = "diffusion";
inline constexpr const char* kRefinePostfilterParams = "iterations=3,k=3";

// The hybrid's (and so the presets') order of a prefilter: last. The motion-compensated hybrid aligns
// and averages the noisy frames, and a single-frame denoiser then sees a shot of several times its
// sample count: against running it first, relMSE 0.57-0.75x OIDN's instead of 0.73-0.85x at 4 spp
// and 0.75-0.90x instead of 0.83-0.92x at 16 on every scene (docs/methods.md, "Prefilter first or
// last"). The study's filters keep first: global PCA and the error threshold on noisy frames ghost
// under a camera pan, which the trust blend cannot take back (camera_pan 16 spp: 1.01x OIDN's against
// 0.89x).
inline constexpr const char* kHybridPrefilterOrder = "last";

// prefilter (a filter name, "" = none) and prefilter_params ("name=value,name=value").
std::vector<ParamSpec> prefilter_params();
// postfilter and postfilter_params, with the given defaults.
std::vector<ParamSpec> postfilter_params(const char* default_filter = "", const char* default_params = "");

// Sets each name=value of a comma list with ParamSet::set_string. A piece without '=' continues the
// previous value, so "channels=R,G,B" keeps its commas. Throws naming `what` and the piece at fault.
void set_param_list(ParamSet& params, const std::string& list, const std::string& what);
// Whether such a list sets parameter `name`.
bool names_param(const std::string& list, const std::string& name);

// Runs the single-frame filter that parameter `stage` ("prefilter" or "postfilter") names, with
// the parameters of `stage`_params, from input into output. Its results are added to results as
// "STAGE.NAME". Throws when the name is unknown, unusable here, or a temporal filter.
void run_frame_stage(const std::string& stage, const ParamSet& params, const Sequence& input, Sequence& output,
                     const Progress& progress, Results& results);

// The single-frame filter parameter `stage` names, configured from `stage`_params; throws as
// run_frame_stage does. Used to check a configuration before any work, and by the scheduler.
std::unique_ptr<Filter> make_frame_stage(const std::string& stage, const ParamSet& params);
// Adds a stage filter's results to results as "STAGE.NAME".
void add_stage_results(const std::string& stage, const Results& own, Results& results);

// Bytes one thread's single-frame filter holds: the frame, and its working copies of it (a few frames,
// as OIDN's), or a diffusion's working set in double, which it keeps from frame to frame.
double frame_stage_bytes(const Shape& shape);

// True when parameter `stage` exists and names a filter.
bool has_frame_stage(const ParamSet& params, const std::string& stage);
// True when the prefilter runs after the temporal filter (prefilter_order=last): the temporal filter
// works on the noisy frames, the prefilter runs on its result in place of the postfilter, and the
// prefilter's frames of the noisy shot are what the trust blend falls back to. A single-frame denoiser
// given frames a temporal pass has already averaged sees a higher sample count, and leaves less of
// its own error (docs/methods.md, "Trusting time after a prefilter").
bool prefilter_runs_last(const ParamSet& params);
// True when the prefilter runs on the noisy shot before the temporal filter: as its input (first), or
// as what the trust blend falls back to (last, with prefilter_trust).
bool prefilters_noisy_shot(const ParamSet& params);
// True when the temporal filter works on a prefilter's frames (a prefilter, run first).
bool temporal_sees_prefilter(const ParamSet& params);
// True when the postfilter runs: named, and not replaced by a prefilter run last.
bool runs_postfilter(const ParamSet& params);
// Throws when a postfilter other than the filter's default is named with a prefilter run last: it
// would not run.
void check_prefilter_order(const ParamSet& params);
// True when a prefilter runs and the temporal result is to be blended back towards it tile by tile
// where the noisy frames do not support it (prefilter_trust; statfilter/time_trust.hpp).
bool trusts_time_by_tile(const ParamSet& params);
// The trust blend's constants, from the prefilter_trust_* parameters.
TimeTrustOptions time_trust_options(const ParamSet& params);
// True when a prefilter runs and its output is to be scaled to the noisy shot's light (keep_mean).
bool keeps_prefilter_light(const ParamSet& params);
// True when the filter has the nonfinite parameter and it names `policy` ("error" or "repair").
bool nonfinite_policy_is(const ParamSet& params, const char* policy);

}  // namespace statfilter
