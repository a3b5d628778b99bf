// Artifact detection's additions to the C ABI: named filter inputs, the degree map's preview, the
// crop-window list, and merge.
#include <cstring>

#include "api_guard.hpp"
#include "options.hpp"
#include "statfilter/crop_windows.hpp"
#include "statfilter/degree_preview.hpp"
#include "statfilter/rerender_merge.hpp"

using namespace statfilter;
using namespace statfilter::capi;

extern "C" {

sf_status sf_filter_set_input(sf_filter filter, const char* name, sf_sequence sequence) {
    std::string* handle_error = filter ? &filter->last_error : nullptr;
    return guarded(
        [&] {
            sf_filter_s& f = require(filter, "filter");
            f.filter->set_input(require_string(name, "name"), sequence ? sequence->sequence.get() : nullptr);
        },
        handle_error);
}

sf_status sf_filter_set_input_files(sf_filter filter, const char* name, const char* pattern) {
    std::string* handle_error = filter ? &filter->last_error : nullptr;
    return guarded(
        [&] {
            sf_filter_s& f = require(filter, "filter");
            f.filter->set_input_files(require_string(name, "name"), pattern ? pattern : "");
        },
        handle_error);
}

sf_status sf_detect_degree_preview(sf_sequence degree_map, int64_t degree, sf_sequence* preview) {
    return guarded([&] {
        require(preview, "preview") = nullptr;
        *preview = new sf_sequence_s{degree_preview(require_sequence(degree_map, "degree_map"), degree)};
    });
}

sf_status sf_crops_windows(const char* crops_json, sf_crop_window* windows, size_t capacity, size_t* count,
                           int64_t* width, int64_t* height) {
    return guarded([&] {
        size_t& n = require(count, "count");
        n = 0;
        const CropPlan plan = crop_plan_from_json(require_string(crops_json, "crops_json"));
        if (width) *width = plan.width;
        if (height) *height = plan.height;
        size_t total = 0;
        for (const FrameCrops& f : plan.frames)
            for (size_t k = 0; k < f.windows.size(); ++k, ++total) {
                if (!windows || total >= capacity) continue;
                const CropWindow& w = f.windows[k];
                windows[total] = sf_crop_window{f.frame, static_cast<int64_t>(k), w.x, w.y, w.width, w.height};
            }
        n = windows ? std::min(total, capacity) : total;
    });
}

void sf_merge_options_init(sf_merge_options* options) {
    if (!options) return;
    std::memset(options, 0, sizeof *options);
    options->struct_size = sizeof *options;
}

sf_status sf_merge(sf_sequence denoised, sf_sequence rerender, const sf_merge_options* options, sf_sequence output,
                   int64_t* replaced) {
    return guarded([&] {
        if (replaced) *replaced = 0;
        const sf_merge_options o = read_versioned(options, sf_merge_options_init);
        const Sequence& d = require_sequence(denoised, "denoised");
        const Sequence& r = require_sequence(rerender, "rerender");
        Sequence& out = require_sequence(output, "output");
        CropPlan plan;
        MergeOptions mo;
        if (o.crops) {
            plan = crop_plan_from_json(o.crops);
            mo.crops = &plan;
        }
        if (o.mask) mo.mask = o.mask->sequence.get();
        mo.feather = o.feather;
        const int64_t n = merge_rerender(d, r, mo, out, make_progress(o.progress, o.progress_user));
        if (&out != &d) out.copy_attributes_from(d);
        if (replaced) *replaced = n;
    });
}

}  // extern "C"
