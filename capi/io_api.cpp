// sf_pattern_*, sf_sequence_read and sf_sequence_write: files in and out.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "api_guard.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"

using namespace statfilter;
using namespace statfilter::capi;

namespace {

std::string text_or_empty(const char* s) { return s ? std::string(s) : std::string(); }

// Reads the fields of a caller's options struct that its struct_size says it has.
template <class T>
T read_versioned(const T* options, void (*init)(T*)) {
    T copy;
    init(&copy);
    if (!options) return copy;
    if (options->struct_size < sizeof(size_t) || options->struct_size > sizeof(T))
        throw Error(Status::InvalidArgument, "options.struct_size " + std::to_string(options->struct_size) +
                                                 " is not a size this library knows (call the *_init function)");
    std::memcpy(&copy, options, options->struct_size);
    return copy;
}

ColorConversion color_of(const char* config, const char* from, const char* to) {
    ColorConversion c;
    c.config = text_or_empty(config);
    c.from = text_or_empty(from);
    c.to = text_or_empty(to);
    return c;
}

// The level after "name:" (the writer checks the name): a whole number 1-9 for zip and zips, a
// number > 0 for dwaa and dwab, none for the others. OpenEXR would otherwise ignore it silently.
void check_compression_level(const std::string& compression) {
    const size_t colon = compression.find(':');
    if (colon == std::string::npos) return;
    const std::string name = compression.substr(0, colon), level = compression.substr(colon + 1);
    const bool zip = name == "zip" || name == "zips", dwa = name == "dwaa" || name == "dwab";
    if (!zip && !dwa)
        throw Error(Status::InvalidArgument, "EXR compression '" + compression + "': " + name +
                                                 " takes no level (only zip, zips, dwaa and dwab do)");
    char* end = nullptr;
    const double value = level.empty() || std::isspace(static_cast<unsigned char>(level[0]))
                             ? 0.0
                             : std::strtod(level.c_str(), &end);
    const bool number = end && *end == '\0' && std::isfinite(value);
    if (zip && !(number && value == std::floor(value) && value >= 1 && value <= 9))
        throw Error(Status::InvalidArgument, "EXR compression '" + compression +
                                                 "': the zip level must be a whole number from 1 to 9");
    if (dwa && !(number && value > 0))
        throw Error(Status::InvalidArgument, "EXR compression '" + compression +
                                                 "': the DWA level must be a number above 0 (default 45)");
}

}  // namespace

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
        const sf_read_options o = read_versioned(options, sf_read_options_init);
        ReadOptions ro;
        ro.channels = text_or_empty(o.channels);
        ro.frames = text_or_empty(o.frames);
        ro.color = color_of(o.ocio_config, o.colorspace_in, o.colorspace_out);
        ro.progress = make_progress(o.progress, o.progress_user);
        auto seq = read_sequence(require_string(pattern, "pattern"), ro);
        auto* handle = new sf_sequence_s;
        handle->sequence = std::move(seq);
        *out = handle;
    });
}

sf_status sf_sequence_write(sf_sequence sequence, const char* pattern, const sf_write_options* options) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        const sf_write_options o = read_versioned(options, sf_write_options_init);
        // A C caller may store any int in the enum: read it as one (an out-of-range enum load is UB in C++).
        int pixel_type = 0;
        static_assert(sizeof pixel_type == sizeof o.pixel_type, "sf_pixel_type is an int-sized enum");
        std::memcpy(&pixel_type, &o.pixel_type, sizeof pixel_type);
        if (pixel_type != SF_PIXEL_HALF && pixel_type != SF_PIXEL_FLOAT)
            throw Error(Status::InvalidArgument, "pixel_type must be SF_PIXEL_HALF or SF_PIXEL_FLOAT");
        WriteOptions wo;
        wo.half = pixel_type == SF_PIXEL_HALF;
        wo.compression = o.compression ? o.compression : "zip";
        check_compression_level(wo.compression);
        wo.color = color_of(o.ocio_config, o.colorspace_in, o.colorspace_out);
        wo.clamp_half = o.half_overflow != 0;
        wo.progress = make_progress(o.progress, o.progress_user);
        write_sequence(seq, require_string(pattern, "pattern"), wo);
    });
}

}  // extern "C"
