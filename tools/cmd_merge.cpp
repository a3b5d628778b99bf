// statfilter merge DENOISED RERENDER OUT --crops crops.json: splice re-rendered pixels (full frames or
// crop-window renders) into the denoised sequence.
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "cli_common.hpp"
#include "cli_json.hpp"
#include "commands.hpp"

namespace statfilter_cli {
namespace {

const std::string kWindowToken = "{window}";

std::string read_text_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Failure("cannot read '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::vector<sf_crop_window> windows_of(const std::string& crops, int64_t& width, int64_t& height) {
    size_t count = 0;
    check(sf_crops_windows(crops.c_str(), nullptr, 0, &count, &width, &height));
    std::vector<sf_crop_window> windows(count);
    if (count) check(sf_crops_windows(crops.c_str(), windows.data(), count, &count, nullptr, nullptr));
    windows.resize(count);
    return windows;
}

std::string pattern_for_frame(const std::string& pattern, int64_t frame) {
    size_t needed = 0;
    check(sf_pattern_format(pattern.c_str(), frame, nullptr, 0, &needed));
    std::string out(needed, '\0');
    check(sf_pattern_format(pattern.c_str(), frame, out.data(), out.size(), &needed));
    out.resize(needed ? needed - 1 : 0);
    return out;
}

// The returned options point into channels and frames: keep both alive while they are used.
sf_read_options plain_read_options(const std::string& channels, const std::string& frames, ProgressLine& progress) {
    sf_read_options o;
    sf_read_options_init(&o);
    o.channels = channels.empty() ? nullptr : channels.c_str();
    o.frames = frames.empty() ? nullptr : frames.c_str();
    o.progress = &ProgressLine::callback;
    o.progress_user = &progress;
    return o;
}

// Byte address of sample (f, y, x, c) of a sequence's memory.
float* sample(float* data, const sf_strides& s, int64_t f, int64_t y, int64_t x, int64_t c) {
    return reinterpret_cast<float*>(reinterpret_cast<char*>(data) + f * s.frame + y * s.row + x * s.pixel + c * s.channel);
}

// One file per crop window ({window} in the pattern), each window-sized or frame-sized, pasted into
// blank full-size frames: the frames that have windows, in ascending order.
void read_window_renders(const std::string& pattern, const std::vector<sf_crop_window>& windows, const sf_shape& full,
                         const std::string& channels, ProgressLine& progress, SequenceHandle& out) {
    std::vector<int64_t> frames;
    for (const auto& w : windows)
        if (frames.empty() || frames.back() != w.frame) frames.push_back(w.frame);
    std::map<int64_t, int64_t> index;
    for (size_t i = 0; i < frames.size(); ++i) index[frames[i]] = static_cast<int64_t>(i);
    check(sf_sequence_create(sf_shape{static_cast<int64_t>(frames.size()), full.height, full.width, full.channels}, out.out()));
    for (size_t i = 0; i < frames.size(); ++i) check(sf_sequence_set_frame_number(out.get(), static_cast<int64_t>(i), frames[i]));
    float* dst = nullptr;
    sf_strides ds{};
    check(sf_sequence_data(out.get(), &dst, &ds));
    for (const auto& w : windows) {
        std::string name = pattern;
        name.replace(name.find(kWindowToken), kWindowToken.size(), std::to_string(w.index));
        name = pattern_for_frame(name, w.frame);
        SequenceHandle part;
        const sf_read_options o = plain_read_options(channels, "", progress);
        check(sf_sequence_read(name.c_str(), &o, part.out()));
        const sf_shape s = part.shape();
        const bool whole = s.width == full.width && s.height == full.height;
        if (!whole && (s.width != w.width || s.height != w.height))
            throw Failure("'" + name + "' is " + std::to_string(s.width) + " x " + std::to_string(s.height) +
                          "; window " + std::to_string(w.index) + " of frame " + std::to_string(w.frame) + " is " +
                          std::to_string(w.width) + " x " + std::to_string(w.height) + " (or give the whole " +
                          std::to_string(full.width) + " x " + std::to_string(full.height) + " frame)");
        if (s.channels != full.channels)
            throw Failure("'" + name + "' has " + std::to_string(s.channels) + " channels, the denoised frames " +
                          std::to_string(full.channels) + " (use --channels)");
        float* src = nullptr;
        sf_strides ss{};
        check(sf_sequence_data(part.get(), &src, &ss));
        const int64_t f = index[w.frame], ox = whole ? w.x : 0, oy = whole ? w.y : 0;
        for (int64_t y = 0; y < w.height; ++y)
            for (int64_t x = 0; x < w.width; ++x)
                for (int64_t c = 0; c < full.channels; ++c)
                    *sample(dst, ds, f, w.y + y, w.x + x, c) = *sample(src, ss, 0, oy + y, ox + x, c);
    }
}

}  // namespace

int cmd_merge(int argc, char** argv) {
    const Args args(argc, argv, 2, {"float", "clamp-half", "json", "quiet", "help"},
                    merged({kInputOptions, kOutputOptions, {"crops", "mask", "feather"}}));
    if (args.flag("help")) {
        std::printf(
            "usage: statfilter merge DENOISED RERENDER OUT --crops CROPS.json [--mask M.####.exr] [--feather N]\n\n"
            "Splices re-rendered pixels into the denoised sequence and writes the result to OUT. The pixels\n"
            "replaced in a frame are its crop windows (as 'statfilter detect --crops' wrote them), or with\n"
            "--mask only the flagged pixels (which must lie inside the windows), or --mask alone.\n\n"
            "RERENDER is either\n"
            "  full frames, e.g. rr.####.exr: only the frames that have windows are read;\n"
            "  one file per crop window, with {window} in the pattern, e.g. rr.{window}.####.exr, where\n"
            "  {window} is the window's index within its frame (0, 1, ... as listed in the JSON) and each\n"
            "  file is the size of its window (a crop render) or of the whole frame.\n\n"
            "  --crops PATH            the crop windows (JSON)\n"
            "  --mask PATTERN          the mask (non-zero = re-rendered pixel)\n"
            "  --feather N             blend the re-render in over N pixels inside the edge of each region\n"
            "                          (default 0; keep N <= the windows' padding so flagged pixels are\n"
            "                          replaced entirely)\n"
            "  --json, --quiet\n\n%s\n%s",
            kInputHelp, kOutputHelp);
        return 0;
    }
    if (args.positionals().size() != 3) throw UsageError("merge takes DENOISED RERENDER OUT (see --help)");
    if (!args.has("crops") && !args.has("mask")) throw UsageError("merge needs --crops, --mask or both");
    const std::string den_pattern = args.positionals()[0], rr_pattern = args.positionals()[1], out_pattern = args.positionals()[2];
    check_exr_output(out_pattern);
    int64_t feather = 0;
    try {
        size_t used = 0;
        feather = std::stoll(args.option("feather", "0"), &used);
        if (used != args.option("feather", "0").size() || feather < 0) throw std::invalid_argument("");
    } catch (const std::exception&) {
        throw UsageError("--feather takes a whole number of pixels >= 0, got '" + args.option("feather") + "'");
    }

    ProgressLine progress(args.flag("quiet") || args.flag("json"));
    std::string crops;
    std::vector<sf_crop_window> windows;
    int64_t crops_width = 0, crops_height = 0;
    if (args.has("crops")) {
        crops = read_text_file(args.option("crops"));
        windows = windows_of(crops, crops_width, crops_height);
    }
    SequenceHandle denoised, mask, rerender, output;
    read_input(args, den_pattern, progress, denoised);
    const sf_shape shape = denoised.shape();
    // The windows lie inside the frame size the JSON declares: it must be the sequence's before any
    // window is pasted into frames of the sequence's size.
    if (args.has("crops") && (crops_width != shape.width || crops_height != shape.height))
        throw Failure("'" + args.option("crops") + "': the crop windows are for " + std::to_string(crops_width) +
                      " x " + std::to_string(crops_height) + " frames; the denoised frames are " +
                      std::to_string(shape.width) + " x " + std::to_string(shape.height));
    if (args.has("mask")) {
        const std::string frame_list = args.option("frames");  // outlives the read, as the options need
        const std::string every = "*";  // every channel of the mask; outlives the read, as frame_list
        const sf_read_options o = plain_read_options(every, frame_list, progress);
        check(sf_sequence_read(args.option("mask").c_str(), &o, mask.out()));
    }

    // The frames that need re-rendered pixels.
    std::vector<int64_t> frames;
    if (!windows.empty()) {
        for (const auto& w : windows)
            if (frames.empty() || frames.back() != w.frame) frames.push_back(w.frame);
    } else if (args.has("mask")) {
        const sf_shape m = mask.shape();
        float* data = nullptr;
        sf_strides st{};
        check(sf_sequence_data(mask.get(), &data, &st));
        for (int64_t f = 0; f < m.frames; ++f) {
            bool any = false;
            for (int64_t y = 0; y < m.height && !any; ++y)
                for (int64_t x = 0; x < m.width && !any; ++x)
                    for (int64_t c = 0; c < m.channels && !any; ++c) any = *sample(data, st, f, y, x, c) != 0.0f;
            int64_t number = 0;
            check(sf_sequence_frame_number(mask.get(), f, &number));
            if (any) frames.push_back(number);
        }
    }
    if (frames.empty())
        throw Failure(std::string("nothing to merge: ") + (args.has("crops") ? "the crop windows list no window" : "the mask flags no pixel") +
                      " (the denoised sequence is already the result)");

    if (rr_pattern.find(kWindowToken) != std::string::npos) {
        if (windows.empty()) throw UsageError("a RERENDER pattern with {window} needs --crops");
        read_window_renders(rr_pattern, windows, shape, args.option("channels"), progress, rerender);
    } else {
        // The options point into these strings: they must outlive the read.
        const std::string channels = args.option("channels"), frame_list = frame_list_text(frames);
        const sf_read_options o = plain_read_options(channels, frame_list, progress);
        check(sf_sequence_read(rr_pattern.c_str(), &o, rerender.out()));
    }

    check(sf_sequence_create(shape, output.out()));
    sf_merge_options mo;
    sf_merge_options_init(&mo);
    mo.crops = crops.empty() ? nullptr : crops.c_str();
    mo.mask = args.has("mask") ? mask.get() : nullptr;
    mo.feather = feather;
    mo.progress = &ProgressLine::callback;
    mo.progress_user = &progress;
    int64_t replaced = 0;
    check(sf_merge(denoised.get(), rerender.get(), &mo, output.get(), &replaced));
    write_output(args, output, out_pattern, progress);
    progress.finish();

    const double fraction = static_cast<double>(replaced) / static_cast<double>(shape.frames * shape.height * shape.width);
    if (args.flag("json")) {
        std::printf("{\"output\": %s, \"replaced_pixel_frames\": %lld, \"replaced_fraction\": %s, \"frames\": %zu, "
                    "\"windows\": %zu}\n",
                    json_string(out_pattern).c_str(), static_cast<long long>(replaced), json_number(fraction).c_str(),
                    frames.size(), windows.size());
    } else if (!args.flag("quiet")) {
        std::printf("merged %lld re-rendered pixel-frames (%.3f%%) into %zu frames\n", static_cast<long long>(replaced),
                    100 * fraction, frames.size());
    }
    return 0;
}

}  // namespace statfilter_cli
