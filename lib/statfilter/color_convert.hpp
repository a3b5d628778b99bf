// Colour-space conversion of interleaved float pixels through OpenColorIO.
#pragma once
#include <cstdint>

#include "statfilter/sequence_io.hpp"

namespace statfilter {

// Converts width x height pixels of 3 or 4 interleaved channels in place.
void convert_colors(float* pixels, int64_t width, int64_t height, int64_t channels, const ColorConversion& conversion);

// Throws Error(InvalidArgument/NotFound) if the conversion cannot be built (checked before any work).
void check_color_conversion(const ColorConversion& conversion, int64_t channels);

}  // namespace statfilter
