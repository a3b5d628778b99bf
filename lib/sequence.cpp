#include "statfilter/sequence.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <new>

#include "statfilter/error.hpp"
#include "statfilter/frame_metadata.hpp"

namespace statfilter {

std::string to_string(const Shape& s) {
    return std::to_string(s.frames) + " frames of " + std::to_string(s.width) + " x " + std::to_string(s.height) +
           " x " + std::to_string(s.channels) + " channels";
}

void validate_shape(const Shape& s) {
    if (s.frames < 1 || s.height < 1 || s.width < 1 || s.channels < 1)
        throw Error(Status::InvalidArgument, "invalid shape (" + to_string(s) + "): every dimension must be >= 1");
    constexpr int64_t max_pixels = std::numeric_limits<int32_t>::max();
    if (s.height > max_pixels || s.width > max_pixels || s.height * s.width > max_pixels)
        throw Error(Status::InvalidArgument, "invalid shape (" + to_string(s) + "): a frame of " +
                                                 std::to_string(s.width) + " x " + std::to_string(s.height) +
                                                 " exceeds 2^31 - 1 pixels");
    // frames * pixels * channels * sizeof(float) must fit in a signed 64-bit byte count.
    const int64_t max_bytes = std::numeric_limits<int64_t>::max() / 4;
    const int64_t per_frame = s.height * s.width;  // < 2^31
    if (s.channels > max_bytes / per_frame || s.frames > max_bytes / (per_frame * s.channels))
        throw Error(Status::InvalidArgument, "invalid shape (" + to_string(s) + "): size overflows");
}

Strides contiguous_strides(const Shape& s) {
    Strides st;
    st.channel = sizeof(float);
    st.pixel = st.channel * s.channels;
    st.row = st.pixel * s.width;
    st.frame = st.row * s.height;
    return st;
}

Sequence::Sequence(const Shape& shape) : shape_(shape) {
    validate_shape(shape);
    strides_ = contiguous_strides(shape);
    const auto n = static_cast<uint64_t>(shape.samples());
    if (n > std::numeric_limits<size_t>::max() / sizeof(float))
        throw Error(Status::OutOfMemory, "sequence too large: " + to_string(shape));
    try {
        owned_.reset(new float[n]());
    } catch (const std::bad_alloc&) {
        throw Error(Status::OutOfMemory, "out of memory allocating " + to_string(shape));
    }
    data_ = owned_.get();
    init_attributes();
}

Sequence::Sequence(float* data, const Shape& shape, const Strides& strides) : shape_(shape), strides_(strides), data_(data) {
    validate_shape(shape);
    if (!data) throw Error(Status::InvalidArgument, "data is NULL");
    for (int64_t s : {strides.channel, strides.pixel, strides.row, strides.frame})
        if (s < 0 || s % static_cast<int64_t>(sizeof(float)) != 0)
            throw Error(Status::InvalidArgument, "strides must be non-negative multiples of 4 bytes");
    if (reinterpret_cast<uintptr_t>(data) % alignof(float) != 0)
        throw Error(Status::InvalidArgument, "data is not aligned to 4 bytes");
    init_attributes();
}

Sequence::~Sequence() = default;

void Sequence::init_attributes() {
    channel_names_.clear();
    for (int64_t c = 0; c < shape_.channels; ++c) channel_names_.push_back("C" + std::to_string(c));
    frame_numbers_.resize(shape_.frames);
    for (int64_t f = 0; f < shape_.frames; ++f) frame_numbers_[f] = f + 1;
    metadata_.assign(static_cast<size_t>(shape_.frames), FrameMetadata());
}

bool Sequence::is_contiguous() const {
    const Strides c = contiguous_strides(shape_);
    auto same = [](int64_t n, int64_t a, int64_t b) { return n == 1 || a == b; };
    return same(shape_.channels, strides_.channel, c.channel) && same(shape_.width, strides_.pixel, c.pixel) &&
           same(shape_.height, strides_.row, c.row) && same(shape_.frames, strides_.frame, c.frame);
}

void Sequence::get_frame(int64_t f, float* dst) const {
    const int64_t n = shape_.pixels() * shape_.channels;
    if (is_contiguous()) {
        std::memcpy(dst, reinterpret_cast<const char*>(data_) + f * strides_.frame, n * sizeof(float));
        return;
    }
    for (int64_t y = 0; y < shape_.height; ++y)
        for (int64_t x = 0; x < shape_.width; ++x)
            for (int64_t c = 0; c < shape_.channels; ++c) *dst++ = at(f, y, x, c);
}

void Sequence::set_frame(int64_t f, const float* src) {
    const int64_t n = shape_.pixels() * shape_.channels;
    if (is_contiguous()) {
        std::memcpy(reinterpret_cast<char*>(data_) + f * strides_.frame, src, n * sizeof(float));
        return;
    }
    for (int64_t y = 0; y < shape_.height; ++y)
        for (int64_t x = 0; x < shape_.width; ++x)
            for (int64_t c = 0; c < shape_.channels; ++c) at(f, y, x, c) = *src++;
}

void Sequence::copy_samples_from(const Sequence& other) {
    if (other.shape() != shape_)
        throw Error(Status::InvalidArgument,
                    "shape mismatch: " + to_string(other.shape()) + " into " + to_string(shape_));
    if (other.data() == data_ && other.strides_.channel == strides_.channel && other.strides_.pixel == strides_.pixel &&
        other.strides_.row == strides_.row && other.strides_.frame == strides_.frame)
        return;  // in place
    std::vector<float> frame(static_cast<size_t>(shape_.pixels() * shape_.channels));
    for (int64_t f = 0; f < shape_.frames; ++f) {
        other.get_frame(f, frame.data());
        set_frame(f, frame.data());
    }
}

void Sequence::copy_attributes_from(const Sequence& other) {
    if (other.shape().frames != shape_.frames || other.shape().channels != shape_.channels)
        throw Error(Status::InvalidArgument, "attribute copy needs the same frames and channels");
    channel_names_ = other.channel_names_;
    frame_numbers_ = other.frame_numbers_;
    metadata_ = other.metadata_;
    source_ = other.source_;
}

ChannelStats channel_stats(const Sequence& seq, int64_t channel) {
    const Shape& s = seq.shape();
    if (channel < 0 || channel >= s.channels)
        throw Error(Status::InvalidArgument, "channel index " + std::to_string(channel) + " out of range");
    ChannelStats st;
    double sum = 0;
    int64_t finite = 0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) {
                const double v = seq.at(f, y, x, channel);
                if (std::isnan(v)) {
                    ++st.nan_count;
                } else if (std::isinf(v)) {
                    ++st.inf_count;
                } else {
                    ++finite;
                    sum += v;
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            }
    if (finite > 0) {
        st.min = lo;
        st.max = hi;
        st.mean = sum / static_cast<double>(finite);
    }
    return st;
}

}  // namespace statfilter
