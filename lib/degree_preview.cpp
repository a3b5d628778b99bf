#include "statfilter/degree_preview.hpp"

#include <algorithm>

#include "statfilter/error.hpp"

namespace statfilter {

std::unique_ptr<Sequence> degree_preview(const Sequence& degree_map, int64_t degree) {
    const Shape& s = degree_map.shape();
    if (s.frames != 1 || s.channels != 1)
        throw Error(Status::InvalidArgument, "a degree map is one frame of one channel, got " + std::to_string(s.frames) +
                                                 " frames of " + std::to_string(s.channels) + " channels");
    if (degree < 0) throw Error(Status::InvalidArgument, "the highest degree must be >= 0, got " + std::to_string(degree));
    auto rgb = std::make_unique<Sequence>(Shape{1, s.height, s.width, 3});
    rgb->channel_names() = {"R", "G", "B"};
    rgb->frame_numbers() = degree_map.frame_numbers();
    for (int64_t y = 0; y < s.height; ++y)
        for (int64_t x = 0; x < s.width; ++x) {
            const float d = degree_map.at(0, y, x, 0);
            float r = 0.9f, g = 0.1f, b = 0.1f;  // no degree explains it (or not a number)
            if (d <= static_cast<float>(degree)) {
                const float t = degree > 0 ? std::clamp(d / static_cast<float>(degree), 0.0f, 1.0f) : 0.0f;
                r = std::clamp(1.8f * t - 0.5f, 0.0f, 1.0f);
                g = std::clamp(0.15f + 0.85f * t, 0.0f, 1.0f);
                b = std::clamp(0.55f - 0.5f * t, 0.0f, 1.0f);
            }
            rgb->at(0, y, x, 0) = r, rgb->at(0, y, x, 1) = g, rgb->at(0, y, x, 2) = b;
        }
    return rgb;
}

}  // namespace statfilter
