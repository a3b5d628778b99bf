// statfilter detect DENOISED --noisy NOISY: the pixel-frames still wrong after denoising, as a mask
// per frame, crop windows (JSON) for a renderer, a degree map and its preview.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "cli_common.hpp"
#include "cli_images.hpp"
#include "cli_json.hpp"
#include "commands.hpp"

namespace statfilter_cli {
namespace {

std::string dashes_to_underscores(std::string s) {
    std::replace(s.begin(), s.end(), '-', '_');
    return s;
}

// Writes text to path through a temporary file in the same directory, renamed into place.
void write_text_atomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw Failure("cannot write '" + path + "' (does its directory exist?)");
        out << text;
        out.flush();
        if (!out) {
            std::remove(tmp.c_str());
            throw Failure("cannot write '" + path + "'");
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw Failure("cannot write '" + path + "'");
    }
}

void write_result_image(const FilterHandle& filter, const char* name, const std::string& pattern, bool as_float,
                        ProgressLine& progress) {
    SequenceHandle image;
    filter.check(sf_filter_result_sequence(filter.get(), name, image.out()));
    sf_write_options o;
    sf_write_options_init(&o);
    o.pixel_type = as_float ? SF_PIXEL_FLOAT : SF_PIXEL_HALF;
    o.progress = &ProgressLine::callback;
    o.progress_user = &progress;
    check(sf_sequence_write(image.get(), pattern.c_str(), &o));
}

// The degree map for people (sf_detect_degree_preview: the picture a detect plan writes too).
void write_degree_preview(const FilterHandle& filter, int64_t degree, const std::string& path) {
    SequenceHandle map, rgb;
    filter.check(sf_filter_result_sequence(filter.get(), "degree_map", map.out()));
    check(sf_detect_degree_preview(map.get(), degree, rgb.out()));
    sf_write_options o;
    sf_write_options_init(&o);
    o.pixel_type = SF_PIXEL_FLOAT;  // PNG stores 8 bits; OpenImageIO converts
    check(sf_sequence_write(rgb.get(), path.c_str(), &o));
}

void print_detect_parameters() {
    FilterHandle filter("detect");
    int count = 0;
    filter.check(sf_filter_param_count(filter.get(), &count));
    for (int i = 0; i < count; ++i) {
        sf_param_info info;
        info.struct_size = sizeof info;
        filter.check(sf_filter_param_info(filter.get(), i, &info));
        std::string name = info.name;
        std::replace(name.begin(), name.end(), '_', '-');
        std::printf("  --%-22s %s (default %s%s%s)\n", name.c_str(), info.description, info.default_value,
                    info.choices && *info.choices ? "; " : "", info.choices ? info.choices : "");
    }
}

}  // namespace

int cmd_detect(int argc, char** argv) {
    const Args args(argc, argv, 2, {"json", "quiet", "help"},
                    merged({kInputOptions, {"noisy", "mask", "crops", "degree-map", "preview", "score"}}),
                    filter_parameter_names("detect"));
    if (args.flag("help")) {
        std::printf(
            "usage: statfilter detect DENOISED --noisy NOISY [--mask M.####.exr] [--crops C.json] [options]\n\n"
            "Finds the pixel-frames of a denoised sequence that are still wrong, for a renderer to render\n"
            "again: the residual NOISY - DENOISED, averaged over a small window, is fitted per pixel by\n"
            "polynomials over time (degree 0..D, the smallest whose mean absolute residual is below delta);\n"
            "the fit estimates the denoiser's error, and pixel-frames whose estimated relMSE exceeds the\n"
            "threshold are flagged. Without --noisy the regression sees the denoised sequence alone, which\n"
            "finds far fewer of the real errors (docs/detect.md).\n\n"
            "  --noisy PATTERN          the noisy render DENOISED was made from\n"
            "  --mask PATTERN           write the mask, one EXR per frame (1 = re-render this pixel)\n"
            "  --crops PATH             write the crop windows as JSON (rectangles per frame, row 0 at the top)\n"
            "  --degree-map PATH        write the degree map, one float EXR (D + 1: no degree explains the pixel)\n"
            "  --preview PATH.png       false-colour preview of the degree map (red: no degree explains it)\n"
            "  --score PATTERN          write the estimated relMSE of each pixel-frame (float EXR per frame)\n"
            "  --json                   report on stdout\n  --quiet, -q\n\n"
            "parameters (from the library):\n");
        print_detect_parameters();
        std::printf("\n%s", kInputHelp);
        return 0;
    }
    if (args.positionals().size() != 1) throw UsageError("detect takes one DENOISED pattern (see --help)");
    const std::string in = args.positionals()[0];
    FilterHandle filter("detect");
    for (const auto& [name, value] : args.extras())
        filter.check(sf_filter_set_string(filter.get(), dashes_to_underscores(name).c_str(), value.c_str()));
    int64_t degree = 0;
    filter.check(sf_filter_get_int(filter.get(), "degree", &degree));

    ProgressLine progress(args.flag("quiet") || args.flag("json"));
    SequenceHandle denoised, noisy, output;
    read_input(args, in, progress, denoised);
    if (args.has("noisy")) {
        read_input(args, args.option("noisy"), progress, noisy);
        filter.check(sf_filter_set_input(filter.get(), "noisy", noisy.get()));
    }
    // Every output checked before the detection runs (frame token, format, directory, not an input frame).
    const std::vector<std::pair<std::string, std::string>> outputs = {
        {"mask", "mask"}, {"score", "score"}, {"degree-map", "degree_map"}, {"preview", "degree_map"}};
    for (const auto& [option, result] : outputs)
        if (args.has(option))
            check_save_outputs(filter, {{result, args.option(option)}}, in, args.option("frames"),
                               args.has("noisy") ? args.option("noisy") : std::string());
    check(sf_sequence_create(denoised.shape(), output.out()));
    filter.check(sf_filter_set_progress(filter.get(), &ProgressLine::callback, &progress));
    filter.check(sf_filter_execute(filter.get(), denoised.get(), output.get()));
    filter.check(sf_filter_set_input(filter.get(), "noisy", nullptr));

    if (args.has("mask")) write_result_image(filter, "mask", args.option("mask"), false, progress);
    if (args.has("score")) write_result_image(filter, "score", args.option("score"), true, progress);
    if (args.has("degree-map")) write_result_image(filter, "degree_map", args.option("degree-map"), true, progress);
    if (args.has("preview")) write_degree_preview(filter, degree, args.option("preview"));
    const char* crops = nullptr;
    filter.check(sf_filter_result_string(filter.get(), "crops", &crops));
    if (args.has("crops")) write_text_atomically(args.option("crops"), crops);
    progress.finish();

    int count = 0;
    filter.check(sf_filter_result_count(filter.get(), &count));
    std::vector<std::pair<std::string, std::string>> results;
    for (int i = 0; i < count; ++i) {
        const char* name = nullptr;
        filter.check(sf_filter_result_name(filter.get(), i, &name));
        const std::string n = name;
        if (n == "crops" || n == "mask" || n == "score" || n == "degree_map") continue;
        results.emplace_back(n, json_filter_result(filter.get(), name));
    }
    auto number = [&](const char* name) {
        double v = 0;
        filter.check(sf_filter_result_float(filter.get(), name, &v));
        return v;
    };
    if (args.flag("json")) {
        std::string j = "{\n  \"input\": " + json_string(in) + ",\n  \"noisy\": " +
                        (args.has("noisy") ? json_string(args.option("noisy")) : std::string("null"));
        for (const auto& [name, value] : results) j += ",\n  " + json_string(name) + ": " + value;
        j += "\n}\n";
        std::fputs(j.c_str(), stdout);
    } else if (!args.flag("quiet")) {
        const char* source = "";
        filter.check(sf_filter_result_string(filter.get(), "source", &source));
        std::printf("flagged %.3f%% of pixel-frames (%.0f); %.0f crop windows in %.0f frames cover %.3f%%\n"
                    "source %s, delta %.4g, mean degree %.2f, %.2f%% of pixels unexplained at degree %lld\n",
                    100 * number("flagged_fraction"), number("flagged_pixel_frames"), number("window_count"),
                    number("frames_with_windows"), 100 * number("window_fraction"), source, number("delta"),
                    number("mean_degree"), 100 * number("unexplained_fraction"), static_cast<long long>(degree));
    }
    return 0;
}

}  // namespace statfilter_cli
