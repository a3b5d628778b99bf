#include "statfilter/filter_registry.hpp"

#include "filters/builtin_filters.hpp"
#include "statfilter/error.hpp"

namespace statfilter {

const std::vector<FilterEntry>& filter_registry() {
    static const std::vector<FilterEntry> registry = {
        {"copy", "identity: writes the input unchanged (proves the I/O path)", [] { return make_copy_filter(); }},
        {"pca", "global temporal PCA: keeps the top temporal components of the whole sequence",
         [] { return make_pca_filter(); }},
        {"error-threshold", "per-pixel truncation of the temporal basis by the pooled Delta(error) test",
         [] { return make_error_threshold_filter(); }},
        {"moving-basis", "temporal PCA over a sliding window of frames around each frame",
         [] { return make_moving_basis_filter(); }},
        {"diffusion", "single-frame anisotropic diffusion on HDR floats, frames in parallel",
         [] { return make_diffusion_filter(); }},
        {"motion", "motion maps only: alpha (global, 1 = stationary) and beta (per frame, 1 = moving) as image results",
         [] { return make_motion_filter(); }},
        {"hybrid", "temporal PCA where still, moving basis or single-frame diffusion where things move",
         [] { return make_hybrid_filter(); }},
    };
    return registry;
}

const FilterEntry& find_filter(const std::string& name) {
    for (const auto& e : filter_registry())
        if (e.name == name) return e;
    std::string known;
    for (const auto& e : filter_registry()) known += (known.empty() ? "" : ", ") + e.name;
    throw Error(Status::NotFound, "unknown filter '" + name + "' (filters: " + known + ")");
}

std::unique_ptr<Filter> create_filter(const std::string& name) { return find_filter(name).create(); }

}  // namespace statfilter
