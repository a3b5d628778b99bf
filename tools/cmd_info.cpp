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
    "Frames found (and missing), size and windows, channels and layers, what the default channel\n"
    "selection takes, and per-channel min/mean/max and NaN/Inf counts of a frame sequence such as\n"
    "beauty.####.exr, beauty.%04d.exr or one file. Without --channels every channel is shown.\n"
    "Frames whose data windows differ are read on the display window, 0 outside each frame's own.\n"
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

// The channels a read without --channels takes, as the library chooses them for the first frame.
std::string default_channels(const std::string& pattern, int64_t first_frame) {
    size_t needed = 0;
    check(sf_pattern_format(pattern.c_str(), first_frame, nullptr, 0, &needed));
    std::string path(needed, '\0');
    check(sf_pattern_format(pattern.c_str(), first_frame, path.data(), needed, &needed));
    path.resize(needed - 1);
    if (sf_channel_selection(path.c_str(), nullptr, nullptr, 0, &needed) != SF_OK)
        return std::string("none: ") + sf_last_error();  // a file of data passes only
    std::string list(needed, '\0');
    check(sf_channel_selection(path.c_str(), nullptr, list.data(), needed, &needed));
    list.resize(needed - 1);
    return list;
}

// "L.R,L.G,L.B,M.X" as "L.{R,G,B} M.X": a Blender file's default is many channels of a few layers.
std::string grouped(const std::string& list) {
    std::vector<std::pair<std::string, std::vector<std::string>>> groups;
    size_t start = 0;
    while (start < list.size()) {
        size_t comma = list.find(',', start);
        if (comma == std::string::npos) comma = list.size();
        const std::string name = list.substr(start, comma - start);
        const size_t dot = name.rfind('.');
        const std::string layer = dot == std::string::npos ? "" : name.substr(0, dot + 1);
        if (groups.empty() || groups.back().first != layer) groups.push_back({layer, {}});
        groups.back().second.push_back(name.substr(layer.size()));
        start = comma + 1;
    }
    std::string out;
    for (const auto& [layer, names] : groups) {
        std::string inner;
        for (const auto& n : names) inner += (inner.empty() ? "" : ",") + n;
        out += (out.empty() ? "" : " ") + layer + (names.size() > 1 && !layer.empty() ? "{" + inner + "}" : inner);
    }
    return out;
}

std::string window_text(const sf_window& w) {
    return std::to_string(w.width) + " x " + std::to_string(w.height) + " at (" + std::to_string(w.x) + ", " +
           std::to_string(w.y) + ")";
}

std::string window_json(const sf_window& w) {
    return "{\"x\": " + std::to_string(w.x) + ", \"y\": " + std::to_string(w.y) + ", \"width\": " +
           std::to_string(w.width) + ", \"height\": " + std::to_string(w.height) + "}";
}

bool same(const sf_window& a, const sf_window& b) {
    return a.x == b.x && a.y == b.y && a.width == b.width && a.height == b.height;
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
    if (args.option("channels").empty()) read_args.set_option("channels", "*");  // show every channel
    read_input(read_args, pattern, progress, seq);
    progress.finish();

    std::vector<int64_t> numbers(static_cast<size_t>(seq.shape().frames));
    for (size_t f = 0; f < numbers.size(); ++f)
        check(sf_sequence_frame_number(seq.get(), static_cast<int64_t>(f), &numbers[f]));
    const std::string by_default = default_channels(pattern, numbers.front());
    sf_window window{}, display{};
    check(sf_sequence_frame_windows(seq.get(), 0, &window, &display, nullptr));
    std::vector<int64_t> cropped;  // frames whose own data window is smaller than the window read
    for (size_t f = 0; f < numbers.size(); ++f) {
        sf_window own{};
        check(sf_sequence_frame_windows(seq.get(), static_cast<int64_t>(f), nullptr, nullptr, &own));
        if (!same(own, window)) cropped.push_back(numbers[f]);
    }

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
        j += "  \"data_window\": " + window_json(window) + ",\n";
        j += "  \"display_window\": " + window_json(display) + ",\n";
        j += "  \"cropped_frames\": " + json_string(frame_list_text(cropped)) + ",\n";
        j += "  \"default_channels\": " + json_string(by_default) + ",\n";
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
    if (!same(window, display))
        std::printf("  window    %s of the display window %s\n", window_text(window).c_str(), window_text(display).c_str());
    if (!cropped.empty())
        std::printf("  cropped   frames %s have a smaller data window: read on the window above, 0 outside theirs\n",
                    frame_list_text(cropped).c_str());
    std::printf("  default   %s\n", grouped(by_default).c_str());
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
