// statfilter copy|denoise IN OUT: read a sequence, run a filter over it, write the result.
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "cli_common.hpp"
#include "cli_images.hpp"
#include "cli_json.hpp"
#include "cli_run_setup.hpp"
#include "commands.hpp"

namespace statfilter_cli {
namespace {

const char* type_name(sf_param_type t) {
    switch (t) {
    case SF_PARAM_INT: return "int";
    case SF_PARAM_FLOAT: return "float";
    case SF_PARAM_STRING: return "text";
    }
    return "?";
}

// The parameter table of a filter, from the library itself.
void print_parameters(const std::string& name) {
    FilterHandle filter(name);
    int count = 0;
    filter.check(sf_filter_param_count(filter.get(), &count));
    const char* description = sf_filter_description(name.c_str());
    std::printf("  %s: %s\n", name.c_str(), description ? description : "");
    for (int i = 0; i < count; ++i) {
        sf_param_info info;
        info.struct_size = sizeof info;
        filter.check(sf_filter_param_info(filter.get(), i, &info));
        std::string detail = type_name(info.type);
        if (info.choices && *info.choices) detail += ": " + std::string(info.choices);
        std::printf("    --%-20s %s (%s; default %s)\n", info.name, info.description, detail.c_str(),
                    info.default_value);
    }
}

// OUT, or --into PATTERN: copies of the input frames with the filtered channels put back.
std::string output_pattern(const Args& args) {
    if (!args.has("into")) {
        if (args.positionals().size() != 2) throw UsageError("expected IN and OUT patterns (see --help)");
        return args.positionals()[1];
    }
    if (args.positionals().size() != 1)
        throw UsageError("with --into give only IN: --into PATTERN is the output");
    for (const char* option : {"float", "compression", "tiled"})
        if (args.flag(option) || args.has(option))
            throw UsageError(std::string("--into keeps each part's own pixel types, compression and tiling: --") +
                             option + " does not apply");
    if (args.option("into").empty()) throw UsageError("--into needs an output pattern");
    return args.option("into");
}

int run_filter(const Args& args, const std::string& method) {
    if (args.positionals().empty()) throw UsageError("expected IN and OUT patterns (see --help)");
    const std::string in = args.positionals()[0], out = output_pattern(args);
    check_exr_output(out);
    const auto saves = parse_save_list(args.option("save"));  // checked before any work
    sf_run_options run = run_options(args);
    FilterHandle filter(method);
    set_filter_parameters(filter, args);
    check_save_list(filter, method, saves);
    check_save_outputs(filter, saves, in, args.option("frames"), out);
    set_vectors_input(filter, args, method);

    const auto start = std::chrono::steady_clock::now();
    ProgressLine progress(args.flag("quiet"));
    IoSettings io(args);
    io.write.into = args.has("into") ? 1 : 0;
    run.progress = &ProgressLine::callback;
    run.progress_user = &progress;
    // Reads, filters and writes, streamed where the method allows; everything checked before any work.
    filter.check(sf_filter_run(filter.get(), in.c_str(), &io.read, out.c_str(), &io.write, &run));
    save_image_results(filter, saves, progress);
    progress.finish();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    int result_count = 0;
    filter.check(sf_filter_result_count(filter.get(), &result_count));
    std::vector<std::pair<std::string, std::string>> results;
    for (int i = 0; i < result_count; ++i) {
        const char *name = nullptr, *value = nullptr;
        filter.check(sf_filter_result_name(filter.get(), i, &name));
        filter.check(sf_filter_result_string(filter.get(), name, &value));
        results.emplace_back(name, value);
    }
    auto result_int = [&](const char* name) {
        double v = 0;
        return sf_filter_result_float(filter.get(), name, &v) == SF_OK ? static_cast<int64_t>(v) : int64_t{0};
    };
    const sf_shape shape{result_int("run.frames"), result_int("run.height"), result_int("run.width"),
                         result_int("run.channels")};
    // What the user must know whatever the verbosity (e.g. noise that is the same in every frame).
    for (const auto& [name, value] : results)
        if (name == "warning") std::fprintf(stderr, "statfilter: warning: %s\n", value.c_str());
    if (args.flag("json")) {
        std::string j = "{\n  \"input\": " + json_string(in) + ",\n  \"output\": " + json_string(out) +
                        ",\n  \"method\": " + json_string(method) + ",\n  \"frames\": " + std::to_string(shape.frames) +
                        ",\n  \"width\": " + std::to_string(shape.width) + ",\n  \"height\": " +
                        std::to_string(shape.height) + ",\n  \"channels\": " + std::to_string(shape.channels) +
                        ",\n  \"seconds\": " + json_number(seconds) + ",\n  \"results\": {";
        for (size_t i = 0; i < results.size(); ++i)
            j += (i ? ", " : "") + json_string(results[i].first) + ": " + json_filter_result(filter.get(), results[i].first.c_str());
        j += "}\n}\n";
        std::fputs(j.c_str(), stdout);
    } else if (!args.flag("quiet")) {
        std::fprintf(stderr, "statfilter: %s: %lld frames of %lld x %lld in %.2f s", method.c_str(),
                     static_cast<long long>(shape.frames), static_cast<long long>(shape.width),
                     static_cast<long long>(shape.height), seconds);
        for (const auto& [name, value] : results) std::fprintf(stderr, ", %s %s", name.c_str(), value.c_str());
        std::fprintf(stderr, "\n");
    }
    return 0;
}

const std::set<std::string> kFlags = {"float", "clamp-half", "json", "quiet", "help", "overwrite"};
// --into PATTERN: copy and denoise only (a plan writes frames of its own).
const char* const kIntoHelp =
    "  --into PATTERN          instead of OUT: write each frame into a copy of its input file, the filtered\n"
    "                          channels in place, every other part, channel and header kept as it was\n";

}  // namespace

int cmd_copy(int argc, char** argv) {
    const Args args(argc, argv, 2, kFlags, merged({kInputOptions, kOutputOptions, kRunOptions, {"into"}}), {});
    if (args.flag("help")) {
        std::printf("usage: statfilter copy IN OUT|--into PATTERN [options]\n\nReads a sequence and writes it unchanged through the "
                    "filter path (bit-exact with --float).\n\n%s\n%s\n%s%s  --json, --quiet\n", kInputHelp, kOutputHelp, kRunHelp, kIntoHelp);
        return 0;
    }
    return run_filter(args, "copy");
}

int cmd_denoise(int argc, char** argv) {
    const Args args(argc, argv, 2, kFlags, merged({kInputOptions, kOutputOptions, kRunOptions, {"method", "save", "vectors", "into"}}));
    if (args.flag("help")) {
        std::printf("usage: statfilter denoise IN OUT|--into PATTERN [--quality fast|balanced|high | --method NAME] [--PARAM VALUE ...]\n"
                    "                           [options]\n\n"
                    "Filters a frame sequence. --quality picks the method for the scene (it is the parameter of\n"
                    "method auto; docs/benchmarks.md has the speed/accuracy map behind it). Without --method the\n"
                    "method is %s at quality balanced (%s with --prefilter, e.g. --prefilter oidn).\n"
                    "Methods and their parameters (from the library):\n",
                    kDefaultMethod, kDefaultMethodWithPrefilter);
        for (int i = 0; i < sf_filter_count(); ++i) print_parameters(sf_filter_name(i));
        std::printf("\n%s\n%s\n%s%s  --save NAME=PATH[,...]  write image results, e.g. rank_map=ranks.exr (PNG: false colour)\n"
                    "%s  --json                  report on stdout\n  --quiet, -q\n", kInputHelp, kOutputHelp, kRunHelp, kIntoHelp,
                    kVectorsHelp);
        return 0;
    }
    return run_filter(args, denoise_method(args));
}

}  // namespace statfilter_cli
