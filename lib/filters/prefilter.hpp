// The prefilter stage of the temporal filters: a single-frame filter (the oidn plugin, diffusion,
// any single-frame plugin) runs on every frame first; the temporal filter then works on its output,
// which removes the flicker a single-frame denoiser leaves. Filter::execute runs it for any filter
// whose parameters include "prefilter", so no filter repeats it.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "statfilter/params.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

// prefilter (a filter name, "" = none) and prefilter_params ("name=value,name=value").
std::vector<ParamSpec> prefilter_params();

// Sets each name=value of a comma list with ParamSet::set_string. A piece without '=' continues the
// previous value, so "channels=R,G,B" keeps its commas. Throws naming `what` and the piece at fault.
void set_param_list(ParamSet& params, const std::string& list, const std::string& what);

// Runs the prefilter the parameters name on input into a new sequence (with input's attributes);
// nullptr when none is named. The prefilter's results are added to results as "prefilter.NAME".
std::unique_ptr<Sequence> run_prefilter(const ParamSet& params, const Sequence& input, const Progress& progress,
                                        Results& results);

}  // namespace statfilter
