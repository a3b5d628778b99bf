// statfilter info PATTERN: what a sequence holds, before anyone filters it.
#include <cstdio>
#include <map>

#include "cli_common.hpp"
#include "cli_json.hpp"
#include "commands.hpp"

namespace statfilter_cli {
namespace {

const char* const kHelp =
    "usage: statfilter info PATTERN [options]\n"
    "\n"
    "Frames found (and missing), size, channels and layers, and per-channel min/mean/max and\n"
    "NaN/Inf counts of a frame sequence such as beauty.####.exr, beauty.%04d.exr or one file.\n"
    "\n"
    "  --json                  machine-readable report on stdout\n"
    "  --quiet, -q             no progress on stderr\n";

struct Found {
    std::vector<int64_t> frames, missing;
};

Found scan_frames(const std::string& pattern) {
    size_t count = 0;
    check(sf_pattern_frames(pattern.c_str(), nullptr, 0, &count));
    Found found;
    found.frames.resize(count);
    check(sf_pattern_frames(pattern.c_str(), found.frames.data(), count, &count));
    found.frames.resize(count);
    for (size_t i = 1; i < found.frames.size(); ++i)
        for (int64_t f = found.frames[i - 1] + 1; f < found.frames[i]; ++f) found.missing.push_back(f);
    return found;
}

// Layers are the channel-name prefixes before the last dot ("ViewLayer.Combined" of "ViewLayer.Combined.R").
std::vector<std::string> layers_of(const std::vector<std::string>& channels) {
    std::vector<std::string> layers;
    for (const auto& name : channels) {
        const size_t dot = name.rfind('.');
        if (dot == std::string::npos) continue;
        const std::string layer = name.substr(0, dot);
        bool seen = false;
        for (const auto& l : layers) seen = seen || l == layer;
        if (!seen) layers.push_back(layer);
    }
    return layers;
}

}  // namespace

int cmd_info(int argc, char** argv) {
    const Args args(argc, argv, 2, {"json", "quiet", "help"}, kInputOptions, {});
    if (args.flag("help")) {
        std::printf("%s\n%s", kHelp, kInputHelp);
        return 0;
    }
    if (args.positionals().size() != 1) throw UsageError("info takes one PATTERN (see statfilter info --help)");
    const std::string pattern = args.positionals()[0];

    Found found = scan_frames(pattern);
    // Read what is there (the chosen frames, or every frame found, gaps and all).
    std::string frames = args.option("frames");
    if (frames.empty()) frames = frame_list_text(found.frames);
    ProgressLine progress(args.flag("quiet") || args.flag("json"));
    SequenceHandle seq;
    Args read_args = args;
    read_args.set_option("frames", frames);
    read_input(read_args, pattern, progress, seq);
    progress.finish();

    const sf_shape shape = seq.shape();
    std::vector<std::string> channels;
    std::vector<sf_channel_stats> stats(static_cast<size_t>(shape.channels));
    for (int64_t c = 0; c < shape.channels; ++c) {
        channels.push_back(seq.channel_name(c));
        check(sf_sequence_channel_stats(seq.get(), c, &stats[static_cast<size_t>(c)]));
    }
    const std::vector<std::string> layers = layers_of(channels);

    if (args.flag("json")) {
        std::string j = "{\n";
        j += "  \"pattern\": " + json_string(pattern) + ",\n";
        j += "  \"frames\": " + json_string(frames) + ",\n";
        j += "  \"frame_count\": " + std::to_string(shape.frames) + ",\n";
        j += "  \"missing_frames\": " + json_string(frame_list_text(found.missing)) + ",\n";
        j += "  \"width\": " + std::to_string(shape.width) + ",\n";
        j += "  \"height\": " + std::to_string(shape.height) + ",\n";
        j += "  \"layers\": [";
        for (size_t i = 0; i < layers.size(); ++i) j += (i ? ", " : "") + json_string(layers[i]);
        j += "],\n  \"channels\": [\n";
        for (size_t c = 0; c < channels.size(); ++c) {
            const auto& s = stats[c];
            j += "    {\"name\": " + json_string(channels[c]) + ", \"min\": " + json_number(s.min) +
                 ", \"mean\": " + json_number(s.mean) + ", \"max\": " + json_number(s.max) +
                 ", \"nan\": " + std::to_string(s.nan_count) + ", \"inf\": " + std::to_string(s.inf_count) + "}" +
                 (c + 1 < channels.size() ? ",\n" : "\n");
        }
        j += "  ]\n}\n";
        std::fputs(j.c_str(), stdout);
        return 0;
    }
    std::printf("%s\n", pattern.c_str());
    std::printf("  frames    %lld (%s)\n", static_cast<long long>(shape.frames), frames.c_str());
    if (!found.missing.empty())
        std::printf("  missing   %zu (%s)\n", found.missing.size(), frame_list_text(found.missing).c_str());
    std::printf("  size      %lld x %lld\n", static_cast<long long>(shape.width), static_cast<long long>(shape.height));
    if (!layers.empty()) {
        std::printf("  layers   ");
        for (const auto& l : layers) std::printf(" \"%s\"", l.c_str());
        std::printf("\n");
    }
    std::printf("  %-32s %12s %12s %12s %8s %8s\n", "channel", "min", "mean", "max", "NaN", "Inf");
    for (size_t c = 0; c < channels.size(); ++c) {
        const auto& s = stats[c];
        std::printf("  %-32s %12.6g %12.6g %12.6g %8lld %8lld\n", channels[c].c_str(), s.min, s.mean, s.max,
                    static_cast<long long>(s.nan_count), static_cast<long long>(s.inf_count));
    }
    return 0;
}

}  // namespace statfilter_cli
