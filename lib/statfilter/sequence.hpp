// A frame sequence: F frames of H x W pixels with C float channels, in owned or borrowed memory
// addressed by byte strides, plus the names, frame numbers and metadata that travel with it. No
// image library in this header: the metadata's type belongs to the I/O layer.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace statfilter {

class FrameMetadata;  // statfilter/frame_metadata.hpp: the I/O layer's, not the compute core's

struct Shape {
    int64_t frames = 0, height = 0, width = 0, channels = 0;
    int64_t pixels() const { return height * width; }
    int64_t samples() const { return frames * height * width * channels; }
    bool operator==(const Shape& o) const {
        return frames == o.frames && height == o.height && width == o.width && channels == o.channels;
    }
    bool operator!=(const Shape& o) const { return !(*this == o); }
};

std::string to_string(const Shape& shape);

// Byte distances between neighbours along each axis.
struct Strides {
    int64_t channel = 0, pixel = 0, row = 0, frame = 0;
};

// Throws Error(InvalidArgument) unless every dimension is >= 1, H * W fits in 2^31 - 1 pixels and
// the sample count fits in memory addressing: the check runs before anything is allocated.
void validate_shape(const Shape& shape);

// Contiguous (frame, row, pixel, channel) strides for a shape.
Strides contiguous_strides(const Shape& shape);

// Where a sequence's frames were read from, empty when not from files. Plugins use it to read the
// matching frames of other layers of the same files (e.g. an albedo pass).
struct SequenceSource {
    std::string pattern;
    std::string channels;  // the channel or layer selection it was read with; empty = all
};

class Sequence {
public:
    // Owned, zero-filled, contiguous.
    explicit Sequence(const Shape& shape);
    // Borrowed caller memory; the caller keeps it alive.
    Sequence(float* data, const Shape& shape, const Strides& strides);

    ~Sequence();
    Sequence(const Sequence&) = delete;
    Sequence& operator=(const Sequence&) = delete;

    const Shape& shape() const { return shape_; }
    const Strides& strides() const { return strides_; }
    float* data() { return data_; }
    const float* data() const { return data_; }
    bool owns_memory() const { return static_cast<bool>(owned_); }
    bool is_contiguous() const;

    float& at(int64_t f, int64_t y, int64_t x, int64_t c) {
        return *reinterpret_cast<float*>(reinterpret_cast<char*>(data_) + f * strides_.frame + y * strides_.row +
                                         x * strides_.pixel + c * strides_.channel);
    }
    float at(int64_t f, int64_t y, int64_t x, int64_t c) const { return const_cast<Sequence*>(this)->at(f, y, x, c); }

    // Copies one frame into/out of contiguous (row, pixel, channel) memory.
    void get_frame(int64_t f, float* dst) const;
    void set_frame(int64_t f, const float* src);
    // Copies all samples from another sequence of the same shape (any strides).
    void copy_samples_from(const Sequence& other);
    // Copies names, frame numbers, metadata and source from another sequence with the same frames and channels.
    void copy_attributes_from(const Sequence& other);

    std::vector<std::string>& channel_names() { return channel_names_; }
    const std::vector<std::string>& channel_names() const { return channel_names_; }
    std::vector<int64_t>& frame_numbers() { return frame_numbers_; }
    const std::vector<int64_t>& frame_numbers() const { return frame_numbers_; }
    // Per-frame file metadata (EXR attributes) kept from reading, written back on output.
    std::vector<FrameMetadata>& metadata() { return metadata_; }
    const std::vector<FrameMetadata>& metadata() const { return metadata_; }
    SequenceSource& source() { return source_; }
    const SequenceSource& source() const { return source_; }

private:
    void init_attributes();

    Shape shape_;
    Strides strides_;
    std::unique_ptr<float[]> owned_;
    float* data_ = nullptr;
    std::vector<std::string> channel_names_;
    std::vector<int64_t> frame_numbers_;
    std::vector<FrameMetadata> metadata_;
    SequenceSource source_;
};

struct ChannelStats {
    double min = 0, max = 0, mean = 0;
    int64_t nan_count = 0, inf_count = 0;
};

ChannelStats channel_stats(const Sequence& sequence, int64_t channel);

}  // namespace statfilter
