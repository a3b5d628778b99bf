// Frames parked on disk between two stages that read them in different orders (a per-frame
// prefilter writes frames; the temporal passes read bands of every frame; the moving basis rebuilds
// bands of every frame and hands on whole frames). An unlinked file in
// $TMPDIR (else /tmp): nothing is left behind, even when the process is killed.
#pragma once
#include <memory>
#include <vector>

#include "pipeline/frame_source.hpp"

namespace statfilter {

class ScratchFrames final : public FrameSource {
public:
    // Frames of `shape` with the attributes (names, frame numbers, metadata) of `attributes`.
    ScratchFrames(const Shape& shape, const Sequence& attributes);
    ~ScratchFrames() override;
    ScratchFrames(const ScratchFrames&) = delete;
    ScratchFrames& operator=(const ScratchFrames&) = delete;

    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return attributes_; }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override;
    // Frame index f, contiguous (row, pixel, channel). Safe from several threads for different frames.
    void write_frame(int64_t f, const float* pixels);
    // Rows [y0, y1) of frame f, contiguous (a band's rows of one frame).
    void write_rows(int64_t f, int64_t y0, int64_t y1, const float* rows);
    // Every frame read back from now on with channel c times gain[c] (a prefilter's light restored
    // once the whole shot's is known); empty = as written.
    void set_gain(std::vector<float> gain) { gain_ = std::move(gain); }

private:
    std::vector<float> gain_;
    Shape shape_;
    Sequence attributes_;
    int fd_ = -1;
};

}  // namespace statfilter
