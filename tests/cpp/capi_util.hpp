// Helpers for the C ABI tests: owning handles, building sequences and reading samples through the
// public header only (no core header is visible to these tests).
#pragma once
#include <gtest/gtest.h>

#include <statfilter/statfilter.h>

#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "test_util.hpp"

namespace statfilter_test {

struct SequenceRelease {
    void operator()(sf_sequence s) const { sf_sequence_release(s); }
};
struct FilterRelease {
    void operator()(sf_filter f) const { sf_filter_release(f); }
};
using Seq = std::unique_ptr<std::remove_pointer_t<sf_sequence>, SequenceRelease>;
using Filt = std::unique_ptr<std::remove_pointer_t<sf_filter>, FilterRelease>;

// Asserts a call succeeded, showing the library's message when it did not.
#define EXPECT_SF_OK(call)                                                              \
    do {                                                                                \
        const sf_status sf_status_ = (call);                                            \
        EXPECT_EQ(sf_status_, SF_OK) << #call << ": " << sf_status_name(sf_status_)    \
                                     << ": " << sf_last_error();                        \
    } while (0)
#define ASSERT_SF_OK(call)                                                              \
    do {                                                                                \
        const sf_status sf_status_ = (call);                                            \
        ASSERT_EQ(sf_status_, SF_OK) << #call << ": " << sf_status_name(sf_status_)    \
                                     << ": " << sf_last_error();                        \
    } while (0)

// Expects a call to fail with `expected`, and the thread's message to contain every fragment.
inline void expect_failure(sf_status status, sf_status expected, const std::vector<std::string>& fragments,
                           const char* what = "") {
    EXPECT_EQ(status, expected) << what << ": got " << sf_status_name(status) << " (" << sf_last_error() << ")";
    const std::string message = sf_last_error();
    EXPECT_FALSE(message.empty()) << what;
    for (const std::string& fragment : fragments)
        EXPECT_NE(message.find(fragment), std::string::npos) << what << ": '" << fragment << "' not in: " << message;
}

inline sf_shape shape_of(int64_t frames, int64_t height, int64_t width, int64_t channels) {
    return sf_shape{frames, height, width, channels};
}

inline sf_strides contiguous(const sf_shape& s) {
    const int64_t c = sizeof(float);
    return sf_strides{c, c * s.channels, c * s.channels * s.width, c * s.channels * s.width * s.height};
}

inline int64_t sample_count(const sf_shape& s) { return s.frames * s.height * s.width * s.channels; }

// The address of sample (f, y, x, c) in strided memory.
inline float* sample_at(float* base, const sf_strides& st, int64_t f, int64_t y, int64_t x, int64_t c) {
    return reinterpret_cast<float*>(reinterpret_cast<char*>(base) + f * st.frame + y * st.row + x * st.pixel +
                                    c * st.channel);
}

// Calls fn(f, y, x, c) for every sample index of a shape.
inline void for_each_sample(const sf_shape& s, const std::function<void(int64_t, int64_t, int64_t, int64_t)>& fn) {
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) fn(f, y, x, c);
}

// A new owned sequence (a test failure and nullptr when creation fails).
inline Seq create_sequence(const sf_shape& shape) {
    sf_sequence s = nullptr;
    EXPECT_SF_OK(sf_sequence_create(shape, &s));
    return Seq(s);
}

// A new owned sequence holding value(f, y, x, c), sample_value() by default.
inline Seq filled_sequence(const sf_shape& shape,
                           const std::function<float(int64_t, int64_t, int64_t, int64_t)>& value = sample_value) {
    Seq seq = create_sequence(shape);
    float* data = nullptr;
    sf_strides st{};
    if (!seq || sf_sequence_data(seq.get(), &data, &st) != SF_OK) return seq;
    for_each_sample(shape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        *sample_at(data, st, f, y, x, c) = value(f, y, x, c);
    });
    return seq;
}

// All samples of a sequence in contiguous (frame, row, pixel, channel) order.
inline std::vector<float> samples_of(sf_sequence seq) {
    sf_shape shape{};
    EXPECT_SF_OK(sf_sequence_shape(seq, &shape));
    std::vector<float> out(static_cast<size_t>(sample_count(shape)));
    EXPECT_SF_OK(sf_sequence_copy_to(seq, out.data(), contiguous(shape)));
    return out;
}

inline sf_write_options write_options(sf_pixel_type type = SF_PIXEL_FLOAT) {
    sf_write_options o;
    sf_write_options_init(&o);
    o.pixel_type = type;
    return o;
}

// Reads a pattern; nullptr (and the status in *status) on failure.
inline Seq read_sequence(const std::string& pattern, const char* channels = nullptr, sf_status* status = nullptr) {
    sf_read_options o;
    sf_read_options_init(&o);
    o.channels = channels;
    sf_sequence s = nullptr;
    const sf_status st = sf_sequence_read(pattern.c_str(), &o, &s);
    if (status) *status = st;
    return Seq(s);
}

inline std::string channel_name(sf_sequence seq, int64_t c) {
    const char* name = nullptr;
    EXPECT_SF_OK(sf_sequence_channel_name(seq, c, &name));
    return name ? name : "";
}

inline std::vector<int64_t> frame_numbers(sf_sequence seq) {
    sf_shape shape{};
    EXPECT_SF_OK(sf_sequence_shape(seq, &shape));
    std::vector<int64_t> numbers(static_cast<size_t>(shape.frames));
    for (int64_t i = 0; i < shape.frames; ++i) EXPECT_SF_OK(sf_sequence_frame_number(seq, i, &numbers[i]));
    return numbers;
}

}  // namespace statfilter_test
