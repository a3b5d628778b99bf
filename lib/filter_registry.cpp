#include "statfilter/filter_registry.hpp"

#include "filters/builtin_filters.hpp"
#include "plugins/plugin_registry.hpp"
#include "statfilter/error.hpp"

namespace statfilter {

namespace {

const FilterEntry* find_builtin(const std::string& name) {
    for (const auto& e : filter_registry())
        if (e.name == name) return &e;
    return nullptr;
}

}  // namespace

const std::vector<FilterEntry>& filter_registry() {
    static const std::vector<FilterEntry> registry = {
        {"copy", "identity: writes the input unchanged (proves the I/O path)", [] { return make_copy_filter(); },
         FilterKind::SingleFrame},
        {"pca", "global temporal PCA: keeps the top temporal components of the whole sequence",
         [] { return make_pca_filter(); }},
        {"error-threshold", "per-pixel truncation of the temporal basis by the pooled Delta(error) test",
         [] { return make_error_threshold_filter(); }},
        {"moving-basis", "temporal PCA over a sliding window of frames around each frame",
         [] { return make_moving_basis_filter(); }},
        {"diffusion", "single-frame anisotropic diffusion on HDR floats, frames in parallel",
         [] { return make_diffusion_filter(); }, FilterKind::SingleFrame},
        {"motion", "motion maps only: alpha (global, 1 = stationary) and beta (per frame, 1 = moving) as image results",
         [] { return make_motion_filter(); }},
        {"hybrid", "temporal PCA where still, moving basis or single-frame diffusion where things move",
         [] { return make_hybrid_filter(); }},
        {"auto", "measures how much moves and runs the method the benchmark found best for such a scene",
         [] { return make_auto_filter(); }},
        {"detect", "artifact detection: the pixel-frames still wrong after denoising (mask, crop windows, degree map)",
         [] { return make_detect_filter(); }},
    };
    return registry;
}

std::vector<const FilterEntry*> all_filters() {
    std::vector<const FilterEntry*> out;
    for (const auto& e : filter_registry()) out.push_back(&e);
    for (const FilterEntry* e : plugin_registry().all())
        if (!find_builtin(e->name)) out.push_back(e);  // a built-in's name cannot be taken over
    return out;
}

std::vector<const FilterEntry*> available_filters() {
    std::vector<const FilterEntry*> out;
    for (const FilterEntry* e : all_filters())
        if (e->available()) out.push_back(e);
    return out;
}

const FilterEntry& find_filter(const std::string& name) {
    if (const FilterEntry* e = find_builtin(name)) return *e;
    if (const FilterEntry* e = plugin_registry().find(name)) return *e;
    std::string known;
    for (const FilterEntry* e : available_filters()) known += (known.empty() ? "" : ", ") + e->name;
    throw Error(Status::NotFound, "unknown filter '" + name + "' (filters: " + known +
                                      "; plugins are searched for as statfilter_" + name + ".so in " +
                                      plugin_search_text() + ")");
}

std::unique_ptr<Filter> create_filter(const std::string& name) { return find_filter(name).create(); }

}  // namespace statfilter
