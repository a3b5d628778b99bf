#include "statfilter/degree_preview.hpp"


#include "statfilter/error.hpp"
#include "statfilter/false_colour.hpp"

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
            float colour[3] = {0.9f, 0.1f, 0.1f};  // no degree explains it (or not a number)
            if (d <= static_cast<float>(degree)) false_colour(degree > 0 ? d / static_cast<float>(degree) : 0.0f, colour);
            for (int64_t c = 0; c < 3; ++c) rgb->at(0, y, x, c) = colour[c];
        }
    return rgb;
}

}  // namespace statfilter
