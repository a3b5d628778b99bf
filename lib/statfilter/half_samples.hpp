// Float samples as the half floats an EXR file holds, by one rule wherever they are made (the EXR
// writer, and a plan's tile files when the output is half): a finite value beyond half's range is an
// error naming the frame and channel, or is clamped when asked; the rest round as the library rounds.
#pragma once
#include <cstddef>
#include <cstdint>

#include "statfilter/sequence.hpp"

namespace statfilter {

constexpr float kHalfMax = 65504.0f;

// Throws Status::Numeric for the first finite sample beyond +-65504 of frame index f (interleaved
// channels of `attributes`), naming its frame number and channel.
void check_half_range(const float* samples, size_t count, const Sequence& attributes, int64_t f);
// Samples to half bit patterns (finite ones clamped to +-65504 first when clamp), and back (exact).
void to_half(const float* samples, size_t count, bool clamp, uint16_t* out);
void from_half(const uint16_t* halves, size_t count, float* out);

}  // namespace statfilter
