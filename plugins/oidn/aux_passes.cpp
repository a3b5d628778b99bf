#include "aux_passes.hpp"

#include <memory>

namespace statfilter_oidn {
namespace {

struct Releaser {
    void operator()(sf_sequence s) const { sf_sequence_release(s); }
};
using Sequence = std::unique_ptr<std::remove_pointer_t<sf_sequence>, Releaser>;

bool looks_like_pattern(const std::string& s) {
    return s.find('#') != std::string::npos || s.find('@') != std::string::npos || s.find('%') != std::string::npos;
}

std::string frame_list(const sf_plugin_run& run) {
    std::string list;
    for (int64_t f = 0; f < run.shape.frames; ++f) list += (f ? "," : "") + std::to_string(run.frame_numbers[f]);
    return list;
}

std::string channel_name(sf_sequence s, int64_t c) {
    const char* name = nullptr;
    return sf_sequence_channel_name(s, c, &name) == SF_OK && name ? name : "";
}

// The three channels to use: R,G,B or X,Y,Z by name, else the only three (a fourth named A is alpha).
std::vector<int64_t> pick_channels(sf_sequence s, int64_t channels, const std::string& what) {
    for (const char* names : {"RGB", "XYZ", "rgb", "xyz"}) {
        std::vector<int64_t> picked;
        for (int k = 0; k < 3; ++k)
            for (int64_t c = 0; c < channels; ++c)
                if (channel_name(s, c) == std::string(1, names[k])) {
                    picked.push_back(c);
                    break;
                }
        if (picked.size() == 3) return picked;
    }
    if (channels == 3 || (channels == 4 && channel_name(s, 3) == "A")) return {0, 1, 2};
    std::string list;
    for (int64_t c = 0; c < channels; ++c) list += (c ? "," : "") + channel_name(s, c);
    throw PassError(SF_ERROR_INVALID_ARGUMENT, what + " needs 3 channels (R,G,B or X,Y,Z); it has " + list);
}

}  // namespace

std::vector<float> read_pass(const sf_plugin_run& run, const std::string& what, const std::string& value) {
    sf_read_options options;
    sf_read_options_init(&options);
    const std::string frames = frame_list(run);
    options.frames = frames.c_str();
    std::string pattern = value, where = value;
    if (!looks_like_pattern(value)) {
        // A layer name: of the files the input was read from.
        if (!run.source_pattern || !*run.source_pattern)
            throw PassError(SF_ERROR_INVALID_ARGUMENT,
                            what + " '" + value + "' is not a frame pattern (e.g. albedo.####.exr), and a layer name "
                            "needs an input read from files");
        pattern = run.source_pattern;
        options.channels = value.c_str();
        where = "layer '" + value + "' of " + pattern;
    }
    sf_sequence raw = nullptr;
    if (sf_sequence_read(pattern.c_str(), &options, &raw) != SF_OK)
        throw PassError(SF_ERROR_IO, what + " (" + where + "): " + sf_last_error());
    Sequence pass(raw);
    sf_shape shape{};
    sf_sequence_shape(pass.get(), &shape);
    if (shape.width != run.shape.width || shape.height != run.shape.height)
        throw PassError(SF_ERROR_INVALID_ARGUMENT,
                        what + " (" + where + ") is " + std::to_string(shape.width) + " x " + std::to_string(shape.height) +
                            ", the input " + std::to_string(run.shape.width) + " x " + std::to_string(run.shape.height));
    const std::vector<int64_t> picked = pick_channels(pass.get(), shape.channels, what + " (" + where + ")");
    float* data = nullptr;
    sf_strides strides{};
    sf_sequence_data(pass.get(), &data, &strides);
    std::vector<float> out(static_cast<size_t>(shape.frames * shape.height * shape.width * 3));
    size_t i = 0;
    for (int64_t f = 0; f < shape.frames; ++f)
        for (int64_t y = 0; y < shape.height; ++y)
            for (int64_t x = 0; x < shape.width; ++x)
                for (int64_t c : picked)
                    out[i++] = *reinterpret_cast<const float*>(reinterpret_cast<const char*>(data) + f * strides.frame +
                                                               y * strides.row + x * strides.pixel + c * strides.channel);
    return out;
}

}  // namespace statfilter_oidn
