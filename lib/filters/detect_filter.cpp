// The "detect" filter: artifact detection on a denoised sequence (the main input) with the noisy render
// it came from as the named input "noisy". Its output is its input unchanged; what it finds are its
// results: the images mask, score and degree_map, the crop-window JSON "crops", and counts.
#include "filters/builtin_filters.hpp"
#include "filters/detect_filter.hpp"
#include "statfilter/artifact_detection.hpp"
#include "statfilter/crop_windows.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

class DetectFilter final : public Filter {
public:
    DetectFilter() : Filter(make_params()) {
        accept_input("noisy");
        declare_image_result("mask", ImageFrames::PerFrame);
        declare_image_result("score", ImageFrames::PerFrame);
        declare_image_result("degree_map");
    }

    static std::vector<ParamSpec> make_params() {
        return {
            choice_param("source", "auto", {"auto", "residual", "denoised", "noisy"},
                         "what the regression fits: residual = noisy - denoised (needs the noisy input), or one "
                         "sequence alone; auto = residual when the noisy input is given, else denoised"),
            int_param("degree", "8", 0, 1000000, "highest polynomial degree D of the per-pixel fit over time (<= frames - 1)"),
            float_param("delta", "0", 0, 1e30,
                        "a pixel's degree is the smallest whose mean absolute residual is below delta x its level; "
                        "0 = automatic (max(0.1, 2 x the median relative noise); 0.02 for source=denoised)"),
            int_param("window", "3", 1, 255, "side of the square window (pixels) the series are averaged over"),
            float_param("threshold", "0.01", 0, 1e30, "flag a pixel-frame when its estimated relMSE exceeds this"),
            float_param("frame_outlier", "4", 0, 1e30,
                        "source=residual: a frame the pixel's fit misses by more than this many noise sigmas keeps "
                        "its raw residual (catches errors lasting a few frames); 0 = off"),
            int_param("crop_padding", "1", 0, 100000, "pixels added around flagged pixels in the crop windows"),
            int_param("crop_min_size", "4", 1, 100000, "smallest crop-window width and height (pixels)"),
            int_param("crop_window_cost", "64", 0, 1e12,
                      "merge two crop windows when their bounding box adds at most this many pixels"),
            float_param("memory_mb", "512", 1, 1e7, "working memory budget for bands of rows, in MiB (results do not depend on it)"),
        };
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        const Sequence* noisy = this->input("noisy");
        const DetectOptions o = detect_options(params(), noisy != nullptr);
        const Detection d = detect_artifacts(input, noisy, o, progress);

        const CropOptions co = crop_options(params());
        const CropPlan plan = make_crop_plan(*d.mask, co);

        if (&input != &output) output.copy_samples_from(input);
        const Shape& s = input.shape();
        const double pixel_frames = static_cast<double>(s.frames * s.pixels());
        Results& r = mutable_results();
        r.set("source", std::string(detect_source_name(d.source)));
        r.set("delta", d.delta);
        r.set("noise_ratio", d.noise_ratio);
        r.set("flagged_pixel_frames", static_cast<double>(d.flagged));
        r.set("flagged_fraction", static_cast<double>(d.flagged) / pixel_frames);
        r.set("window_count", static_cast<double>(plan.window_count()));
        r.set("window_pixel_frames", static_cast<double>(plan.window_pixels()));
        r.set("window_fraction", static_cast<double>(plan.window_pixels()) / pixel_frames);
        r.set("frames_with_windows", static_cast<double>(plan.frames.size()));
        r.set("mean_degree", d.mean_degree);
        r.set("unexplained_fraction", static_cast<double>(d.unexplained_pixels) / static_cast<double>(s.pixels()));
        r.set("crops", crop_plan_to_json(plan));
        r.set_image("mask", d.mask);
        r.set_image("score", d.score);
        r.set_image("degree_map", d.degree_map);
    }
};

}  // namespace

DetectOptions detect_options(const ParamSet& params, bool has_noisy) {
    const std::string source = params.get_string("source");
    DetectOptions o;
    if (source == "auto")
        o.source = has_noisy ? DetectSource::Residual : DetectSource::Denoised;
    else
        o.source = source == "residual" ? DetectSource::Residual
                                        : source == "noisy" ? DetectSource::Noisy : DetectSource::Denoised;
    o.degree = params.get_int("degree");
    o.delta = params.get_float("delta");
    o.window = params.get_int("window");
    o.threshold = params.get_float("threshold");
    o.frame_outlier = params.get_float("frame_outlier");
    o.budget_bytes = params.get_float("memory_mb") * 1024.0 * 1024.0;
    return o;
}

CropOptions crop_options(const ParamSet& params) {
    CropOptions co;
    co.padding = params.get_int("crop_padding");
    co.min_size = params.get_int("crop_min_size");
    co.window_cost = params.get_int("crop_window_cost");
    return co;
}

std::unique_ptr<Filter> make_detect_filter() { return std::make_unique<DetectFilter>(); }

}  // namespace statfilter
