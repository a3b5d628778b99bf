// Where a stage's frames come from and where they go. A source hands out rows of any frame (a band
// of scanlines, or a whole frame), so a statistics pass can walk bands of every frame and a
// reconstruction pass whole frames, without the shot ever being in memory. A sink takes finished
// frames in any order and makes them visible together at commit.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "statfilter/sequence.hpp"

namespace statfilter {

class FrameSource {
public:
    virtual ~FrameSource() = default;
    virtual const Shape& shape() const = 0;
    // Names, frame numbers, metadata and origin of the frames (samples zero-sized: shape only).
    virtual const Sequence& attributes() const = 0;
    // Rows [y0, y1) of frame index f into dst, contiguous (row, pixel, channel). Safe to call from
    // several threads at once.
    virtual void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const = 0;
    // The frames as one sequence in memory when the source already holds them (no copy), else null.
    virtual const Sequence* in_memory() const { return nullptr; }
};

class FrameSink {
public:
    virtual ~FrameSink() = default;
    // One finished frame index f, contiguous (row, pixel, channel). Safe to call from several
    // threads at once for different frames.
    virtual void write_frame(int64_t f, const float* pixels) = 0;
    // Makes every frame written visible; before it nothing is (a failed run leaves what was there).
    virtual void commit() = 0;
    // A text attribute for every frame written after this call (provenance: what made the frames).
    // Sinks without metadata ignore it.
    virtual void set_attribute(const std::string& name, const std::string& value) { (void)name, (void)value; }
};

// A sequence in memory as a source (borrowed, zero-copy) and as a sink.
std::unique_ptr<FrameSource> memory_source(const Sequence& sequence);
std::unique_ptr<FrameSink> memory_sink(Sequence& sequence);

}  // namespace statfilter
