#include "options.hpp"

#include "api_guard.hpp"

namespace statfilter::capi {
namespace {

ColorConversion color_of(const char* config, const char* from, const char* to) {
    ColorConversion c;
    c.config = text_or_empty(config);
    c.from = text_or_empty(from);
    c.to = text_or_empty(to);
    return c;
}

}  // namespace

ReadOptions read_options_from(const sf_read_options* options) {
    const sf_read_options o = read_versioned(options, sf_read_options_init);
    ReadOptions ro;
    ro.channels = text_or_empty(o.channels);
    ro.frames = text_or_empty(o.frames);
    ro.color = color_of(o.ocio_config, o.colorspace_in, o.colorspace_out);
    ro.progress = make_progress(o.progress, o.progress_user);
    return ro;
}

WriteOptions write_options_from(const sf_write_options* options) {
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
    wo.color = color_of(o.ocio_config, o.colorspace_in, o.colorspace_out);
    wo.clamp_half = o.half_overflow != 0;
    wo.tile_size = o.tile_size;
    wo.into = o.into != 0;
    wo.progress = make_progress(o.progress, o.progress_user);
    return wo;
}

void check_run_options(const sf_run_options& run, const char* memory_zero, const char* threads_zero) {
    if (run.memory < 0)
        throw Error(Status::InvalidArgument, std::string("run.memory must be >= 0 bytes (0 = ") + memory_zero + ")");
    if (run.threads < 0)
        throw Error(Status::InvalidArgument, std::string("run.threads must be >= 0 (0 = ") + threads_zero + ")");
}

}  // namespace statfilter::capi
