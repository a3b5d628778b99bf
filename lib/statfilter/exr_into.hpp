// Writing filtered channels back into a copy of the EXR frame they were read from (`--into`): every
// part, header and channel of the input frame is kept; the parts holding filtered channels are
// rewritten with those channels replaced, the others copied as their compressed chunks, bit for bit.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "statfilter/frame_metadata.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {

// The pixels of one filtered frame: `channels` interleaved channels on `window` (file coordinates),
// channel c going to targets[c] of the copy.
struct IntoFrame {
    const float* pixels = nullptr;
    PixelWindow window;
    std::vector<FileChannelRef> targets;
};

// Checks that `source` can take the channels back (flat, single-resolution parts, channels not
// subsampled, every target inside the window), naming the file, part and channel; throws if not.
void check_into_source(const std::string& source, const IntoFrame& frame);

// Writes `destination` as a copy of `source` with frame's channels in place (each in the file's own
// pixel type; half values beyond its range are clamped when clamp_half, an error otherwise), the
// `attributes` added to the header of every part that changed.
void write_into_copy(const std::string& source, const std::string& destination, const IntoFrame& frame,
                     const std::vector<std::pair<std::string, std::string>>& attributes, bool clamp_half);

}  // namespace statfilter
