#include "statfilter/false_colour.hpp"

#include <algorithm>
#include <cmath>

#include "statfilter/error.hpp"

namespace statfilter {

void false_colour(float t, float* rgb) {
    const float v = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f);
    rgb[0] = std::clamp(1.8f * v - 0.5f, 0.0f, 1.0f);
    rgb[1] = std::clamp(0.15f + 0.85f * v, 0.0f, 1.0f);
    rgb[2] = std::clamp(0.55f - 0.5f * v, 0.0f, 1.0f);
}

std::unique_ptr<Sequence> false_colour_preview(const Sequence& image) {
    const Shape& s = image.shape();
    if (s.channels < 1) throw Error(Status::InvalidArgument, "a false-colour preview needs an image with a channel");
    auto rgb = std::make_unique<Sequence>(Shape{s.frames, s.height, s.width, 3});
    rgb->channel_names() = {"R", "G", "B"};
    rgb->frame_numbers() = image.frame_numbers();
    float colour[3];
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) {
                false_colour(image.at(f, y, x, 0), colour);
                for (int64_t c = 0; c < 3; ++c) rgb->at(f, y, x, c) = colour[c];
            }
    return rgb;
}

}  // namespace statfilter
