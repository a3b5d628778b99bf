// sf_pattern_*, sf_sequence_read and sf_sequence_write: files in and out.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "api_guard.hpp"
#include "options.hpp"
#include "statfilter/frame_metadata.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

using namespace statfilter;
using namespace statfilter::capi;

extern "C" {

sf_status sf_pattern_frames(const char* pattern, int64_t* numbers, size_t capacity, size_t* count) {
    return guarded([&] {
        require(count, "count") = 0;
        const std::vector<int64_t> frames = FramePattern(require_string(pattern, "pattern")).scan();
        if (frames.empty()) throw Error(Status::NotFound, std::string("no files match '") + pattern + "'");
        if (!numbers) {
            *count = frames.size();
            return;
        }
        const size_t n = std::min(capacity, frames.size());
        std::copy(frames.begin(), frames.begin() + static_cast<std::ptrdiff_t>(n), numbers);
        *count = n;
    });
}

sf_status sf_pattern_format(const char* pattern, int64_t frame, char* buffer, size_t capacity, size_t* needed) {
    return guarded([&] {
        const std::string name = FramePattern(require_string(pattern, "pattern")).format(frame);
        if (needed) *needed = name.size() + 1;
        if (!buffer) {
            if (!needed) throw Error(Status::InvalidArgument, "argument 'buffer' and 'needed' are both NULL");
            return;
        }
        if (capacity < name.size() + 1)
            throw Error(Status::InvalidArgument, "buffer of " + std::to_string(capacity) + " bytes is too small (" +
                                                     std::to_string(name.size() + 1) + " needed)");
        std::memcpy(buffer, name.c_str(), name.size() + 1);
    });
}

void sf_read_options_init(sf_read_options* options) {
    if (!options) return;
    std::memset(options, 0, sizeof *options);
    options->struct_size = sizeof *options;
}

void sf_write_options_init(sf_write_options* options) {
    if (!options) return;
    std::memset(options, 0, sizeof *options);
    options->struct_size = sizeof *options;
    options->pixel_type = SF_PIXEL_HALF;
    options->compression = "zip";
}

sf_status sf_sequence_read(const char* pattern, const sf_read_options* options, sf_sequence* out) {
    return guarded([&] {
        require(out, "out") = nullptr;
        const ReadOptions ro = read_options_from(options);
        auto seq = read_sequence(require_string(pattern, "pattern"), ro);
        auto* handle = new sf_sequence_s;
        handle->sequence = std::move(seq);
        *out = handle;
    });
}

sf_status sf_channel_selection(const char* path, const char* channels, char* buffer, size_t capacity,
                               size_t* needed) {
    return guarded([&] {
        std::string list;
        for (const std::string& name : select_file_channels(require_string(path, "path"), channels ? channels : ""))
            list += (list.empty() ? "" : ",") + name;
        if (needed) *needed = list.size() + 1;
        if (!buffer) {
            if (!needed) throw Error(Status::InvalidArgument, "argument 'buffer' and 'needed' are both NULL");
            return;
        }
        if (capacity < list.size() + 1)
            throw Error(Status::InvalidArgument, "buffer of " + std::to_string(capacity) + " bytes is too small (" +
                                                     std::to_string(list.size() + 1) + " needed)");
        std::memcpy(buffer, list.c_str(), list.size() + 1);
    });
}

sf_status sf_sequence_frame_windows(sf_sequence sequence, int64_t frame, sf_window* data, sf_window* display,
                                    sf_window* file_data) {
    return guarded([&] {
        const Sequence& seq = require_sequence(sequence, "sequence");
        const Shape& s = seq.shape();
        if (frame < 0 || frame >= s.frames)
            throw Error(Status::InvalidArgument, "frame index " + std::to_string(frame) + " is outside 0.." +
                                                     std::to_string(s.frames - 1));
        const FrameMetadata& md = seq.metadata()[static_cast<size_t>(frame)];
        // As the writer places the frame: its read window while the size still matches, else the origin.
        const bool placed = !md.window.empty() && md.window.width == s.width && md.window.height == s.height;
        const PixelWindow own = placed ? md.window : PixelWindow{0, 0, s.width, s.height};
        const PixelWindow shown = placed && !md.display.empty() ? md.display : own;
        const PixelWindow filled = placed && !md.file_data.empty() ? md.file_data : own;
        auto put = [](sf_window* out, const PixelWindow& w) {
            if (out) *out = sf_window{w.x, w.y, w.width, w.height};
        };
        put(data, own);
        put(display, shown);
        put(file_data, filled);
    });
}

sf_status sf_sequence_set_frame_windows(sf_sequence sequence, int64_t frame, const sf_window* data,
                                        const sf_window* display) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        const Shape& s = seq.shape();
        if (frame < -1 || frame >= s.frames)
            throw Error(Status::InvalidArgument, "frame index " + std::to_string(frame) + " is outside 0.." +
                                                     std::to_string(s.frames - 1) + " (or -1 for every frame)");
        const sf_window d = require(data, "data");
        const sf_window shown = display ? *display : d;
        if (d.width != s.width || d.height != s.height)
            throw Error(Status::InvalidArgument, "data window " + std::to_string(d.width) + " x " + std::to_string(d.height) +
                                                     " is not the sequence's size " + std::to_string(s.width) + " x " +
                                                     std::to_string(s.height));
        if (shown.width <= 0 || shown.height <= 0)
            throw Error(Status::InvalidArgument, "the display window must have a positive size");
        for (int64_t f = frame < 0 ? 0 : frame; f < (frame < 0 ? s.frames : frame + 1); ++f) {
            FrameMetadata& md = seq.metadata()[static_cast<size_t>(f)];
            md.window = PixelWindow{d.x, d.y, d.width, d.height};
            md.display = PixelWindow{shown.x, shown.y, shown.width, shown.height};
            md.file_data = PixelWindow{};
        }
    });
}

sf_status sf_sequence_write(sf_sequence sequence, const char* pattern, const sf_write_options* options) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        const WriteOptions wo = write_options_from(options);
        write_sequence(seq, require_string(pattern, "pattern"), wo);
    });
}

}  // extern "C"
