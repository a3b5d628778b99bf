// Factories of the built-in filters, listed by the registry.
#pragma once
#include <memory>

#include "statfilter/filter.hpp"

namespace statfilter {

std::unique_ptr<Filter> make_copy_filter();
std::unique_ptr<Filter> make_pca_filter();
std::unique_ptr<Filter> make_error_threshold_filter();
std::unique_ptr<Filter> make_moving_basis_filter();
std::unique_ptr<Filter> make_diffusion_filter();
std::unique_ptr<Filter> make_motion_filter();
std::unique_ptr<Filter> make_hybrid_filter();
std::unique_ptr<Filter> make_auto_filter();
std::unique_ptr<Filter> make_detect_filter();

// The mean of a one-channel map (e.g. the share of pixels alpha calls moving).
double mean_of_map(const Sequence& map);

// The diffusion filter's parameters and work, shared with the hybrid's single-frame stage.
std::vector<ParamSpec> diffusion_params();
struct DiffusionOptions;
struct DiffusionWorkspace;
DiffusionOptions diffusion_options(const ParamSet& params);
// Every frame diffused, frames in parallel; workspaces (one per worker, grown to fit) are kept for the
// caller's next call.
void diffuse_sequence(const Sequence& input, Sequence& output, const DiffusionOptions& options, const Progress& progress,
                      std::vector<DiffusionWorkspace>& workspaces);

}  // namespace statfilter
