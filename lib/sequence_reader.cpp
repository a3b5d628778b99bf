// Reads a frame sequence: resolves the frames and channels once from the first file and the window
// the frames are read on from every frame's header, then reads every frame straight into the
// sequence's memory (or, streamed, bands of it), checking each file is still as planned.
#include <OpenImageIO/half.h>
#include <OpenImageIO/imageio.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "pipeline/frame_source.hpp"
#include "statfilter/color_convert.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_metadata.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {
namespace {

struct FileChannel {
    int subimage;
    int index;  // within the subimage
    std::string name;
};

// A selected channel and the name it takes in the sequence.
struct Selected {
    FileChannel source;
    std::string name;
};

struct FileLayout {
    std::vector<FileChannel> channels;
    std::vector<OIIO::ImageSpec> specs;  // one per subimage
};

PixelWindow data_window(const OIIO::ImageSpec& spec) { return {spec.x, spec.y, spec.width, spec.height}; }
PixelWindow display_window(const OIIO::ImageSpec& spec) {
    return {spec.full_x, spec.full_y, spec.full_width, spec.full_height};
}

std::string window_text(const PixelWindow& w) {
    return std::to_string(w.width) + " x " + std::to_string(w.height) + " at (" + std::to_string(w.x) + ", " +
           std::to_string(w.y) + ")";
}

PixelWindow bounding_box(const PixelWindow& a, const PixelWindow& b) {
    const int64_t x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
    const int64_t x1 = std::max(a.x + a.width, b.x + b.width), y1 = std::max(a.y + a.height, b.y + b.height);
    return {x0, y0, x1 - x0, y1 - y0};
}

const char* file_kind(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// Only a readable regular file is a frame: a FIFO or a device (say a symlink to /dev/zero) would
// block or never end, and an unreadable file is said to be one, not "not an image".
void check_frame_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw Error(Status::NotFound, "missing frame: '" + path + "' does not exist");
        throw Error(Status::Io, "cannot read '" + path + "': " + std::strerror(errno));
    }
    if (!S_ISREG(st.st_mode))
        throw Error(Status::Io, "cannot read '" + path + "': it is " + file_kind(st.st_mode) + ", not a regular file");
    if (::access(path.c_str(), R_OK) != 0) throw Error(Status::Io, "cannot read '" + path + "': " + std::strerror(errno));
}

std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path) {
    check_frame_file(path);
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        throw Error(Status::Io, "cannot read '" + path + "': " + (why.empty() ? "not a readable image" : why));
    }
    return in;
}

FileLayout read_layout(OIIO::ImageInput& in, const std::string& path) {
    FileLayout layout;
    for (int s = 0; in.seek_subimage(s, 0); ++s) {
        const OIIO::ImageSpec& spec = in.spec();
        for (int c = 0; c < spec.nchannels; ++c)
            layout.channels.push_back({s, c, spec.channel_name(c)});
        layout.specs.push_back(spec);
    }
    if (layout.specs.empty()) throw Error(Status::Io, "cannot read '" + path + "': no image in file");
    return layout;
}

std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        std::string item = text.substr(start, comma - start);
        const size_t b = item.find_first_not_of(' '), e = item.find_last_not_of(' ');
        if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
        start = comma + 1;
    }
    return out;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }
bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string channel_pass(const std::string& channel) {
    const size_t dot = channel.rfind('.');
    if (dot == std::string::npos) return channel;
    const std::string layer = channel.substr(0, dot);
    const size_t before = layer.rfind('.');
    return before == std::string::npos ? layer : layer.substr(before + 1);
}

// Data and auxiliary passes: denoising them as light would corrupt them (normals, depth, IDs,
// colours that multiply the light), and alpha is coverage, not light.
// Names compared without case: renderers and compositors spell them "albedo" as well as "Albedo".
bool is_light_channel(const std::string& channel) {
    static const char* data_passes[] = {"normal", "albedo", "depth",    "z", "vector", "alpha", "mist",
                                        "indexob", "indexma", "uv", "position", "n", "p"};
    std::string lower = channel;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const std::string pass = channel_pass(lower);
    for (const char* d : data_passes)
        if (pass == d) return false;
    if (ends_with(pass, "color") || starts_with(pass, "denoising") || starts_with(pass, "crypto")) return false;
    const size_t dot = lower.rfind('.');
    return (dot == std::string::npos ? lower : lower.substr(dot + 1)) != "a";
}

namespace {

// The default selection: a file without layers (every channel name without a dot, as a plain
// RGB(A) file) is read whole, as before; a file with layers gives its light passes only.
std::vector<Selected> default_channels(const FileLayout& layout, const std::string& path) {
    std::vector<Selected> out;
    bool layered = false;
    for (const auto& ch : layout.channels) layered = layered || ch.name.find('.') != std::string::npos;
    for (const auto& ch : layout.channels)
        if (!layered || is_light_channel(ch.name)) out.push_back({ch, ch.name});
    if (layout.channels.empty()) throw Error(Status::Io, "cannot read '" + path + "': the file has no channels");
    if (out.empty()) {
        std::string available;
        for (const auto& ch : layout.channels) available += (available.empty() ? "" : ", ") + ch.name;
        throw Error(Status::NotFound, "'" + path + "' has no light pass to read by default (channels: " + available +
                                          "): name the channels or layers to read, or * for all");
    }
    return out;
}

// One layer alone is named by its channels' suffixes (R, G, B), as a file of its own would be;
// several names keep the file's full names, so that the layers stay apart in the output.
std::vector<Selected> select_channels(const FileLayout& layout, const std::string& request, const std::string& path) {
    if (request.empty()) return default_channels(layout, path);
    std::vector<Selected> out;
    if (request == "*") {
        for (const auto& ch : layout.channels) out.push_back({ch, ch.name});
        if (out.empty()) throw Error(Status::Io, "cannot read '" + path + "': the file has no channels");
        return out;
    }
    const std::vector<std::string> items = split_list(request);
    if (items.empty())
        throw Error(Status::InvalidArgument, "the channel list '" + request +
                                                 "' names no channel or layer (give names such as R,G,B, * for every "
                                                 "channel, or leave it empty for the light passes)");
    for (const std::string& item : items) {
        bool found = false;
        for (const auto& ch : layout.channels)
            if (ch.name == item) {
                out.push_back({ch, ch.name});
                found = true;
                break;
            }
        if (found) continue;
        const std::string prefix = item + ".";
        for (const auto& ch : layout.channels)
            if (ch.name.compare(0, prefix.size(), prefix) == 0 && ch.name.size() > prefix.size()) {
                out.push_back({ch, items.size() == 1 ? ch.name.substr(prefix.size()) : ch.name});
                found = true;
            }
        if (!found) {
            std::string available;
            for (const auto& ch : layout.channels) available += (available.empty() ? "" : ", ") + ch.name;
            throw Error(Status::NotFound,
                        "no channel or layer '" + item + "' in '" + path + "' (channels: " + available + ")");
        }
    }
    for (size_t i = 0; i < out.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (out[i].source.subimage == out[j].source.subimage && out[i].source.index == out[j].source.index)
                throw Error(Status::InvalidArgument, "the channel list '" + request + "' takes channel '" +
                                                         out[i].source.name + "' of '" + path + "' twice");
    return out;
}

std::vector<int64_t> resolve_frames(const FramePattern& pattern, const std::string& spec) {
    if (!spec.empty()) {
        if (!pattern.has_frame_token() && spec != "1")
            throw Error(Status::InvalidArgument, "pattern '" + pattern.text() + "' has no frame token (#, @ or %0Nd)");
        return parse_frame_spec(spec);
    }
    std::vector<int64_t> frames = pattern.scan();
    if (frames.empty()) throw Error(Status::NotFound, "no files match '" + pattern.text() + "'");
    const int64_t expected = frames.back() - frames.front() + 1;
    if (static_cast<int64_t>(frames.size()) != expected) {
        std::vector<int64_t> missing;
        size_t i = 0;
        for (int64_t f = frames.front(); f <= frames.back(); ++f) {
            if (i < frames.size() && frames[i] == f) {
                ++i;
            } else {
                missing.push_back(f);
            }
        }
        throw Error(Status::NotFound, "gap in sequence '" + pattern.text() + "': frames " +
                                          format_frame_list(missing) + " are missing (found " +
                                          format_frame_list(frames) + "); choose frames explicitly to skip them");
    }
    return frames;
}

// Frames asked for by number must all be there, reported together, before anything is allocated.
void check_frames_exist(const FramePattern& pattern, const std::vector<int64_t>& frames) {
    std::vector<int64_t> missing, found;
    for (int64_t f : frames) {
        struct stat st {};
        if (::stat(pattern.format(f).c_str(), &st) != 0 && (errno == ENOENT || errno == ENOTDIR))
            missing.push_back(f);
        else
            found.push_back(f);
    }
    if (!missing.empty())
        throw Error(Status::NotFound, "sequence '" + pattern.text() + "': frames " + format_frame_list(missing) +
                                          " are missing (found " + (found.empty() ? "none" : format_frame_list(found)) +
                                          "; the first missing is '" + pattern.format(missing.front()) + "')");
}

// Bytes this process may still allocate: the kernel's MemAvailable, within a cgroup's limit.
uint64_t available_memory() {
    uint64_t available = std::numeric_limits<uint64_t>::max();
    std::ifstream meminfo("/proc/meminfo");
    for (std::string line; std::getline(meminfo, line);)
        if (line.rfind("MemAvailable:", 0) == 0) {
            std::istringstream in(line.substr(13));
            uint64_t kb = 0;
            if (in >> kb) available = kb * 1024;
        }
    std::ifstream max_file("/sys/fs/cgroup/memory.max"), current_file("/sys/fs/cgroup/memory.current");
    uint64_t limit = 0, current = 0;
    if (max_file >> limit && current_file >> current) available = std::min(available, limit > current ? limit - current : 0);
    return available;
}

std::string gigabytes(uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GB", static_cast<double>(bytes) / 1e9);
    return text;
}

// A typo such as --frames 1-20000 must not take the machine's memory: refuse what cannot fit.
void check_fits_in_memory(const Shape& shape, const std::string& pattern) {
    const uint64_t needed = static_cast<uint64_t>(shape.frames) * static_cast<uint64_t>(shape.pixels()) *
                            static_cast<uint64_t>(shape.channels) * sizeof(float);
    const uint64_t available = available_memory();
    if (needed > available)
        throw Error(Status::OutOfMemory,
                    "sequence '" + pattern + "': " + std::to_string(shape.frames) + " frames of " +
                        std::to_string(shape.width) + " x " + std::to_string(shape.height) + " x " +
                        std::to_string(shape.channels) + " float channels need " + std::to_string(needed) + " bytes (" +
                        gigabytes(needed) + "), more than the " + gigabytes(available) +
                        " of memory available: read fewer frames (--frames) or channels");
}

// Format bookkeeping that the writer sets itself, and the part's name.
bool bookkeeping(const std::string& name) {
    return name.rfind("oiio:", 0) == 0 || name == "openexr:chunkCount" || name == "compression" || name == "name";
}

// Part 0's attributes (Blender and most renderers put the camera, frame and render statistics
// there), then those of the parts read that part 0 lacks.
FrameMetadata frame_metadata(const FileLayout& layout, const std::vector<int>& parts) {
    FrameMetadata out;
    auto add = [&out](const OIIO::ImageSpec& spec) {
        for (const auto& p : spec.extra_attribs) {
            const std::string name = p.name().string();
            if (!bookkeeping(name) && !out.contains(name)) out.push_back(p);
        }
    };
    add(layout.specs.front());
    for (int s : parts) add(layout.specs[static_cast<size_t>(s)]);
    return out;
}

// Selected channels that sit side by side in one part of the file, read with one call.
struct ChannelRun {
    int subimage = 0, first = 0, count = 0;  // file channels [first, first + count) of the part
    int64_t target = 0;                      // the sequence channel the run starts at
};

std::vector<ChannelRun> channel_runs(const std::vector<Selected>& selection) {
    std::vector<ChannelRun> runs;
    for (size_t c = 0; c < selection.size(); ++c) {
        const FileChannel& src = selection[c].source;
        if (!runs.empty() && runs.back().subimage == src.subimage && runs.back().first + runs.back().count == src.index) {
            ++runs.back().count;
        } else {
            runs.push_back({src.subimage, src.index, 1, static_cast<int64_t>(c)});
        }
    }
    return runs;
}

std::vector<int> parts_of(const std::vector<ChannelRun>& runs) {
    std::vector<int> parts;
    for (const ChannelRun& run : runs)
        if (std::find(parts.begin(), parts.end(), run.subimage) == parts.end()) parts.push_back(run.subimage);
    return parts;
}

// What a sequence is read as, from every frame's header: the channels chosen in the first frame,
// each frame's data window of each run's part, and the one window all frames are read on: their
// common data window, or when the data windows differ (auto-cropped renders, parts of different
// sizes) the box holding the display window and them all, the pixels outside a frame's own data
// window being 0.
struct ReadPlan {
    std::vector<int64_t> frames;
    std::vector<Selected> selection;
    std::vector<ChannelRun> runs;
    PixelWindow window, display;
    std::vector<std::vector<PixelWindow>> part_windows;  // [frame][run]
    std::vector<FrameMetadata> metadata;                  // [frame]

    Shape shape() const {
        return Shape{static_cast<int64_t>(frames.size()), window.height, window.width,
                     static_cast<int64_t>(selection.size())};
    }
};

// Deep parts hold several samples per pixel: refuse them before reading.
void check_flat(const FileLayout& layout, const std::vector<ChannelRun>& runs, const std::string& path) {
    for (const ChannelRun& run : runs)
        if (layout.specs[static_cast<size_t>(run.subimage)].deep)
            throw Error(Status::Unsupported, "cannot read '" + path + "': part " + std::to_string(run.subimage) +
                                                 " is a deep image (several samples per pixel), which statfilter "
                                                 "does not filter: flatten it first (e.g. oiiotool --flatten)");
}

// Every frame must hold the first frame's selected channels, flat, in one display window.
void check_frame_layout(const FileLayout& layout, const ReadPlan& plan, const std::string& path) {
    for (const Selected& sel : plan.selection) {
        const auto s = static_cast<size_t>(sel.source.subimage);
        if (s >= layout.specs.size() || layout.specs[s].nchannels <= sel.source.index ||
            layout.specs[s].channel_name(sel.source.index) != sel.source.name)
            throw Error(Status::NotFound, "'" + path + "' lacks channel '" + sel.source.name + "' found in the first frame");
    }
    check_flat(layout, plan.runs, path);
    for (const ChannelRun& run : plan.runs) {
        const PixelWindow display = display_window(layout.specs[static_cast<size_t>(run.subimage)]);
        if (display != plan.display)
            throw Error(Status::InvalidArgument,
                        "'" + path + "'" + (layout.specs.size() > 1 ? " part " + std::to_string(run.subimage) : "") +
                            " is " + window_text(display) + " (its display window), the first frame is " +
                            window_text(plan.display) + ": the frames of a sequence share one display window");
    }
}

// Adds frame f's header to the plan.
void add_frame(ReadPlan& plan, const FileLayout& layout, const std::string& path) {
    check_frame_layout(layout, plan, path);
    std::vector<PixelWindow> windows;
    PixelWindow own;
    for (const ChannelRun& run : plan.runs) {
        windows.push_back(data_window(layout.specs[static_cast<size_t>(run.subimage)]));
        own = own.empty() ? windows.back() : bounding_box(own, windows.back());
    }
    plan.part_windows.push_back(windows);
    plan.metadata.push_back(frame_metadata(layout, parts_of(plan.runs)));
    plan.metadata.back().file_data = own;
}

// The window all frames are read on, then each frame's windows as the writer will use them.
void finish_plan(ReadPlan& plan) {
    const PixelWindow first = plan.part_windows.front().front();
    bool common = true;
    PixelWindow box = plan.display;
    for (const auto& frame : plan.part_windows)
        for (const PixelWindow& w : frame) {
            common = common && w == first;
            box = bounding_box(box, w);
        }
    plan.window = common ? first : box;
    for (FrameMetadata& md : plan.metadata) {
        md.window = plan.window;
        md.display = plan.display;
        if (md.file_data == plan.window) md.file_data = PixelWindow();
    }
}

// The plan from the first frame alone (its own data window): enough to check the size early.
ReadPlan first_frame_plan(const FramePattern& pattern, const ReadOptions& options) {
    ReadPlan plan;
    plan.frames = resolve_frames(pattern, options.frames);
    const std::string path = pattern.format(plan.frames.front());
    auto in = open_image(path);
    const FileLayout layout = read_layout(*in, path);
    plan.selection = select_channels(layout, options.channels, path);
    plan.runs = channel_runs(plan.selection);
    check_flat(layout, plan.runs, path);
    const OIIO::ImageSpec& spec = layout.specs[static_cast<size_t>(plan.runs.front().subimage)];
    plan.window = data_window(spec);
    plan.display = display_window(spec);
    return plan;
}

// Reads every frame's header into the plan; a missing or different frame fails here, before any pixel.
void read_headers(ReadPlan& plan, const FramePattern& pattern, const Progress& progress) {
    for (size_t f = 0; f < plan.frames.size(); ++f) {
        progress.report(static_cast<double>(f) / static_cast<double>(plan.frames.size()), "open");
        const std::string path = pattern.format(plan.frames[f]);
        auto in = open_image(path);
        add_frame(plan, read_layout(*in, path), path);
    }
    finish_plan(plan);
}

// The frame's header again just before its pixels: it must be as planned.
FileLayout reopen_layout(OIIO::ImageInput& in, const ReadPlan& plan, size_t f, const std::string& path) {
    FileLayout layout = read_layout(in, path);
    check_frame_layout(layout, plan, path);
    for (size_t r = 0; r < plan.runs.size(); ++r)
        if (data_window(layout.specs[static_cast<size_t>(plan.runs[r].subimage)]) != plan.part_windows[f][r])
            throw Error(Status::Io, "'" + path + "' changed while it was being read (its data window is now " +
                                        window_text(data_window(layout.specs[static_cast<size_t>(plan.runs[r].subimage)])) +
                                        ")");
    return layout;
}

std::unique_ptr<Sequence> attributes_of(const ReadPlan& plan, const Shape& shape, const std::string& pattern,
                                        const std::string& channels) {
    auto seq = std::make_unique<Sequence>(shape);
    for (size_t c = 0; c < plan.selection.size(); ++c) seq->channel_names()[c] = plan.selection[c].name;
    seq->source() = SequenceSource{pattern, channels};
    seq->frame_numbers() = plan.frames;
    seq->metadata() = plan.metadata;
    return seq;
}

// Frame f's pixels into `dst` (the plan's window, contiguous, zero where the file has no data).
void read_frame(const std::string& path, const ReadPlan& plan, size_t f, float* dst) {
    auto in = open_image(path);
    reopen_layout(*in, plan, f, path);
    const Shape shape = plan.shape();
    const auto pixel = static_cast<OIIO::stride_t>(shape.channels * sizeof(float));
    for (size_t r = 0; r < plan.runs.size(); ++r) {
        const ChannelRun& run = plan.runs[r];
        const PixelWindow& w = plan.part_windows[f][r];
        float* at = dst + ((w.y - plan.window.y) * shape.width + (w.x - plan.window.x)) * shape.channels + run.target;
        if (!in->read_image(run.subimage, 0, run.first, run.first + run.count, OIIO::TypeDesc::FLOAT, at, pixel,
                            pixel * shape.width, OIIO::AutoStride)) {
            std::string why = in->geterror();
            throw Error(Status::Io, "cannot read '" + path + "': " + (why.empty() ? "read failed" : why));
        }
    }
}

}  // namespace

std::vector<std::string> select_file_channels(const std::string& path, const std::string& channels) {
    auto in = open_image(path);
    std::vector<std::string> out;
    for (const Selected& sel : select_channels(read_layout(*in, path), channels, path)) out.push_back(sel.source.name);
    return out;
}

std::vector<FileChannelRef> locate_file_channels(const std::string& path, const std::string& channels) {
    auto in = open_image(path);
    std::vector<FileChannelRef> out;
    for (const Selected& sel : select_channels(read_layout(*in, path), channels, path))
        out.push_back({sel.source.subimage, sel.source.name});
    return out;
}

std::unique_ptr<Sequence> read_sequence(const std::string& pattern_text, const ReadOptions& options) {
    const FramePattern pattern(pattern_text);
    if (!options.frames.empty()) check_frames_exist(pattern, resolve_frames(pattern, options.frames));
    ReadPlan plan = first_frame_plan(pattern, options);
    // A typo such as --frames 1-20000 is refused from the first frame's size, before every header is read.
    validate_shape(plan.shape());
    check_fits_in_memory(plan.shape(), pattern_text);
    check_color_conversion(options.color, plan.shape().channels);
    read_headers(plan, pattern, Progress());
    const Shape shape = plan.shape();
    validate_shape(shape);
    check_fits_in_memory(shape, pattern_text);

    auto seq = attributes_of(plan, shape, pattern_text, options.channels);  // owned, zero-filled, contiguous
    for (int64_t f = 0; f < shape.frames; ++f) {
        options.progress.report(static_cast<double>(f) / shape.frames, "read");
        read_frame(pattern.format(plan.frames[static_cast<size_t>(f)]), plan, static_cast<size_t>(f), &seq->at(f, 0, 0, 0));
        if (options.color.active())
            convert_colors(&seq->at(f, 0, 0, 0), shape.width, shape.height, shape.channels, options.color);
    }
    options.progress.report(1.0, "read");
    return seq;
}

}  // namespace statfilter

// ---- a sequence opened for reading in pieces (bands of scanlines, whole frames) ----------------

namespace statfilter {
namespace {

// Rows [y0, y1) of a run's part (file coordinates) into dst. read_scanlines does not read tiled
// parts, so those are decoded by whole rows of tiles and the rows asked for copied out.
// The type the run's channels are all stored in when it is half or float, else UNKNOWN.
OIIO::TypeDesc stored_type(const OIIO::ImageSpec& spec, const ChannelRun& run) {
    const OIIO::TypeDesc t = spec.channelformat(run.first);
    if (t != OIIO::TypeDesc::HALF && t != OIIO::TypeDesc::FLOAT) return OIIO::TypeDesc::UNKNOWN;
    for (int c = run.first + 1; c < run.first + run.count; ++c)
        if (spec.channelformat(c) != t) return OIIO::TypeDesc::UNKNOWN;
    return t;
}

// Scanlines [y0, y1) of the run read as stored, a block of rows at a time, and widened to float into
// dst (exactly: every half is a float). Asked for float, the library would allocate a 64 MB buffer
// for each read. Blocks end on multiples of 256 rows from the part's first row, a multiple of every
// EXR compression's chunk height, so no chunk is decoded twice.
template <class Stored>
bool read_stored_rows(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, const ChannelRun& run, int y0, int y1,
                      float* dst, OIIO::stride_t pixel, OIIO::stride_t row) {
    constexpr int kBlockRows = 256;
    std::vector<Stored> block;
    for (int a = y0; a < y1;) {
        const int b = std::min(y1, spec.y + ((a - spec.y) / kBlockRows + 1) * kBlockRows);
        const size_t values_per_row = static_cast<size_t>(spec.width) * static_cast<size_t>(run.count);
        block.resize(static_cast<size_t>(b - a) * values_per_row);
        if (!in.read_scanlines(run.subimage, 0, a, b, 0, run.first, run.first + run.count, OIIO::TypeDesc::UNKNOWN,
                               block.data()))
            return false;
        for (int y = a; y < b; ++y) {
            const Stored* from = block.data() + static_cast<size_t>(y - a) * values_per_row;
            char* to = reinterpret_cast<char*>(dst) + (y - y0) * row;
            for (int x = 0; x < spec.width; ++x) {
                float* px = reinterpret_cast<float*>(to + x * pixel);
                for (int c = 0; c < run.count; ++c) px[c] = static_cast<float>(from[x * run.count + c]);
            }
        }
        a = b;
    }
    return true;
}

bool read_part_rows(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, const ChannelRun& run, int y0, int y1,
                    float* dst, OIIO::stride_t pixel, OIIO::stride_t row) {
    if (spec.tile_width <= 0) {
        const OIIO::TypeDesc stored = stored_type(spec, run);
        if (stored == OIIO::TypeDesc::HALF) return read_stored_rows<half>(in, spec, run, y0, y1, dst, pixel, row);
        if (stored == OIIO::TypeDesc::FLOAT) return read_stored_rows<float>(in, spec, run, y0, y1, dst, pixel, row);
        return in.read_scanlines(run.subimage, 0, y0, y1, 0, run.first, run.first + run.count, OIIO::TypeDesc::FLOAT,
                                 dst, pixel, row);
    }
    const int th = spec.tile_height;
    const int ty0 = spec.y + (y0 - spec.y) / th * th;
    const int ty1 = std::min(spec.y + spec.height, spec.y + (y1 - spec.y + th - 1) / th * th);
    std::vector<float> tiles(static_cast<size_t>(ty1 - ty0) * static_cast<size_t>(spec.width) * run.count);
    if (!in.read_tiles(run.subimage, 0, spec.x, spec.x + spec.width, ty0, ty1, spec.z, spec.z + std::max(1, spec.depth),
                       run.first, run.first + run.count, OIIO::TypeDesc::FLOAT, tiles.data()))
        return false;
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < spec.width; ++x)
            std::copy_n(&tiles[(static_cast<size_t>(y - ty0) * spec.width + x) * run.count], run.count,
                        reinterpret_cast<float*>(reinterpret_cast<char*>(dst) + (y - y0) * row + x * pixel));
    return true;
}

class ExrFrameSource final : public FrameSource {
public:
    ExrFrameSource(const std::string& pattern_text, const ReadOptions& options)
        : pattern_(pattern_text), color_(options.color) {
        plan_ = first_frame_plan(pattern_, options);
        check_color_conversion(options.color, plan_.shape().channels);
        // Every frame's header now, before any pixel: a missing or different frame fails the run
        // before the work starts, and the metadata is at hand for the writer.
        read_headers(plan_, pattern_, options.progress);
        shape_ = plan_.shape();
        validate_shape(shape_);
        attributes_ = attributes_of(plan_, Shape{shape_.frames, 1, 1, shape_.channels}, pattern_text, options.channels);
    }

    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return *attributes_; }

    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        const auto frame = static_cast<size_t>(f);
        const std::string path = pattern_.format(plan_.frames[frame]);
        auto in = open_image(path);
        const FileLayout layout = reopen_layout(*in, plan_, frame, path);
        const auto pixel = static_cast<OIIO::stride_t>(shape_.channels * sizeof(float));
        bool zeroed = false;
        for (size_t r = 0; r < plan_.runs.size(); ++r) {  // all channels of a part in one decode of each chunk
            const ChannelRun& run = plan_.runs[r];
            const PixelWindow& w = plan_.part_windows[frame][r];
            if (w != plan_.window && !zeroed) {  // the part covers less than the window: 0 elsewhere
                std::fill(dst, dst + (y1 - y0) * shape_.width * shape_.channels, 0.0f);
                zeroed = true;
            }
            // The rows of [y0, y1) that the part holds, in window coordinates.
            const int64_t a = std::max(y0, w.y - plan_.window.y), b = std::min(y1, w.y + w.height - plan_.window.y);
            if (a >= b) continue;
            float* at = dst + ((a - y0) * shape_.width + (w.x - plan_.window.x)) * shape_.channels + run.target;
            const int file_y = static_cast<int>(plan_.window.y + a);
            if (!read_part_rows(*in, layout.specs[static_cast<size_t>(run.subimage)], run, file_y,
                                file_y + static_cast<int>(b - a), at, pixel, pixel * shape_.width)) {
                std::string why = in->geterror();
                throw Error(Status::Io, "cannot read '" + path + "': " + (why.empty() ? "read failed" : why));
            }
        }
        if (color_.active()) convert_colors(dst, shape_.width, y1 - y0, shape_.channels, color_);
    }

private:
    FramePattern pattern_;
    ColorConversion color_;
    ReadPlan plan_;
    Shape shape_;
    std::unique_ptr<Sequence> attributes_;
};

}  // namespace

std::unique_ptr<FrameSource> open_frame_source(const std::string& pattern, const ReadOptions& options) {
    return std::make_unique<ExrFrameSource>(pattern, options);
}

}  // namespace statfilter
