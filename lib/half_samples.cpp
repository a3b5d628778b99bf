#include "statfilter/half_samples.hpp"

#include <OpenImageIO/half.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "statfilter/error.hpp"

namespace statfilter {

void check_half_range(const float* samples, size_t count, const Sequence& attributes, int64_t f) {
    for (size_t i = 0; i < count; ++i) {
        const float v = samples[i];
        if (std::isfinite(v) && std::fabs(v) > kHalfMax) {
            const int64_t c = static_cast<int64_t>(i) % attributes.shape().channels;
            throw Error(Status::Numeric, "frame " + std::to_string(attributes.frame_numbers()[static_cast<size_t>(f)]) +
                                             " channel '" + attributes.channel_names()[static_cast<size_t>(c)] + "' holds " +
                                             std::to_string(v) + ", beyond half float's range (65504): write float, or clamp");
        }
    }
}

void to_half(const float* samples, size_t count, bool clamp, uint16_t* out) {
    static_assert(sizeof(half) == sizeof(uint16_t), "half is 16 bits");
    for (size_t i = 0; i < count; ++i) {
        const float v = samples[i];
        const half h = clamp && std::isfinite(v) ? std::max(-kHalfMax, std::min(kHalfMax, v)) : v;
        std::memcpy(out + i, &h, sizeof h);
    }
}

void from_half(const uint16_t* halves, size_t count, float* out) {
    for (size_t i = 0; i < count; ++i) {
        half h;
        std::memcpy(&h, halves + i, sizeof h);
        out[i] = static_cast<float>(h);
    }
}

}  // namespace statfilter
