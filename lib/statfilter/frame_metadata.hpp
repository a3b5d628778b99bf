// The file attributes of one frame (EXR header attributes: camera, frame, render statistics, ...),
// kept from reading and written back on output, with the frame's windows. Only the I/O layer and
// code that reads or sets attributes include this; the core's sequence type holds them without
// knowing what they are.
#pragma once
#include <OpenImageIO/paramlist.h>

#include <cstdint>

namespace statfilter {

// A rectangle of pixels in the file's coordinates (EXR data or display window); width 0 = none.
struct PixelWindow {
    int64_t x = 0, y = 0, width = 0, height = 0;
    bool empty() const { return width <= 0 || height <= 0; }
    bool operator==(const PixelWindow& o) const {
        return x == o.x && y == o.y && width == o.width && height == o.height;
    }
    bool operator!=(const PixelWindow& o) const { return !(*this == o); }
};

class FrameMetadata : public OIIO::ParamValueList {
public:
    // Where the sequence's pixels sit: the output's data window. Empty = at the origin (frames
    // that did not come from files).
    PixelWindow window;
    // The display window the frame belongs to. Empty = the same as `window`.
    PixelWindow display;
    // The frame's own data window in its file when smaller than `window` (auto-cropped renders):
    // the pixels of `window` outside it were read as 0. Empty = the same as `window`.
    PixelWindow file_data;
};

}  // namespace statfilter
