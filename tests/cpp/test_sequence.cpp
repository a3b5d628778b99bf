// The core's sequence model: shape validation, strided (borrowed) memory, copies and statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "statfilter/error.hpp"
#include "statfilter/frame_metadata.hpp"
#include "statfilter/sequence.hpp"
#include "test_util.hpp"

using namespace statfilter;
using statfilter_test::sample_value;

namespace {

constexpr int64_t kF = sizeof(float);
constexpr int64_t kInt64Max = std::numeric_limits<int64_t>::max();

// The status an expression throws, or Ok when it does not throw.
template <class Body>
Status status_of(Body&& body) {
    try {
        body();
    } catch (const Error& e) {
        return e.status();
    }
    return Status::Ok;
}

// Fills a sequence through at() with sample_value().
void fill(Sequence& seq) {
    const Shape& s = seq.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) seq.at(f, y, x, c) = sample_value(f, y, x, c);
}

void expect_samples(const Sequence& seq) {
    const Shape& s = seq.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c)
                    ASSERT_EQ(seq.at(f, y, x, c), sample_value(f, y, x, c)) << f << "," << y << "," << x << "," << c;
}

const Shape kSmall{3, 4, 5, 2};  // frames, height, width, channels

// Channel-planar layout (channel, frame, row, pixel), like a stack of per-channel planes.
Strides planar_strides(const Shape& s) {
    Strides st;
    st.pixel = kF;
    st.row = st.pixel * s.width;
    st.frame = st.row * s.height;
    st.channel = st.frame * s.frames;
    return st;
}

}  // namespace

TEST(Shape, AcceptsOrdinaryShapes) {
    EXPECT_NO_THROW(validate_shape({1, 1, 1, 1}));
    EXPECT_NO_THROW(validate_shape({32, 120, 160, 3}));
    // Exactly 2^31 - 1 pixels is the largest frame allowed.
    EXPECT_NO_THROW(validate_shape({1, 1, std::numeric_limits<int32_t>::max(), 1}));
}

TEST(Shape, RejectsZeroAndNegativeDimensions) {
    for (const Shape& s : {Shape{0, 4, 4, 1}, Shape{1, 0, 4, 1}, Shape{1, 4, 0, 1}, Shape{1, 4, 4, 0},
                           Shape{-1, 4, 4, 1}, Shape{1, -4, 4, 1}, Shape{1, 4, -4, 1}, Shape{1, 4, 4, -3}})
        EXPECT_EQ(status_of([&] { validate_shape(s); }), Status::InvalidArgument) << to_string(s);
}

TEST(Shape, RejectsFramesBeyond32BitPixelCounts) {
    // 65536 x 65536 = 2^32 pixels: must fail in validation, before the constructor allocates 16 GiB.
    EXPECT_EQ(status_of([] { validate_shape({1, 65536, 65536, 1}); }), Status::InvalidArgument);
    EXPECT_EQ(status_of([] { Sequence seq(Shape{1, 65536, 65536, 1}); }), Status::InvalidArgument);
    EXPECT_EQ(status_of([] { validate_shape({1, 1, int64_t{1} << 31, 1}); }), Status::InvalidArgument);
    // Dimensions whose product wraps around in 64 bits must not sneak through.
    EXPECT_EQ(status_of([] { validate_shape({1, int64_t{1} << 32, int64_t{1} << 32, 1}); }), Status::InvalidArgument);
    try {
        validate_shape({1, 65536, 65536, 1});
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("2^31 - 1"), std::string::npos) << e.what();
    }
}

TEST(Shape, RejectsByteCountsOverflowing64Bits) {
    EXPECT_EQ(status_of([] { validate_shape({kInt64Max / 4, 1000, 1000, 1}); }), Status::InvalidArgument);
    EXPECT_EQ(status_of([] { validate_shape({kInt64Max, 1, 1, 1}); }), Status::InvalidArgument);
    EXPECT_EQ(status_of([] { validate_shape({int64_t{1} << 40, 65535, 65535, 4}); }), Status::InvalidArgument);
    EXPECT_EQ(status_of([] { validate_shape({1, 1000, 1000, kInt64Max / 2}); }), Status::InvalidArgument);
    // The byte count (samples * 4) overflows although the sample count alone does not.
    EXPECT_EQ(status_of([] { validate_shape({int64_t{1} << 61, 1, 1, 1}); }), Status::InvalidArgument);
}

TEST(Sequence, OwnedIsZeroedContiguousAndNamed) {
    Sequence seq(kSmall);
    EXPECT_TRUE(seq.owns_memory());
    EXPECT_TRUE(seq.is_contiguous());
    const Strides st = seq.strides();
    EXPECT_EQ(st.channel, kF);
    EXPECT_EQ(st.pixel, kF * kSmall.channels);
    EXPECT_EQ(st.row, st.pixel * kSmall.width);
    EXPECT_EQ(st.frame, st.row * kSmall.height);
    for (int64_t i = 0; i < kSmall.samples(); ++i) ASSERT_EQ(seq.data()[i], 0.0f);
    EXPECT_EQ(seq.channel_names(), (std::vector<std::string>{"C0", "C1"}));
    EXPECT_EQ(seq.frame_numbers(), (std::vector<int64_t>{1, 2, 3}));
    EXPECT_EQ(seq.metadata().size(), 3u);
}

TEST(Sequence, PlanarWrapAddressesTheRightSamples) {
    std::vector<float> buffer(static_cast<size_t>(kSmall.samples()));
    const Strides st = planar_strides(kSmall);
    Sequence seq(buffer.data(), kSmall, st);
    EXPECT_FALSE(seq.owns_memory());
    EXPECT_FALSE(seq.is_contiguous());
    fill(seq);
    // Every sample must land at channel-major position ((c * F + f) * H + y) * W + x.
    for (int64_t c = 0; c < kSmall.channels; ++c)
        for (int64_t f = 0; f < kSmall.frames; ++f)
            for (int64_t y = 0; y < kSmall.height; ++y)
                for (int64_t x = 0; x < kSmall.width; ++x)
                    ASSERT_EQ(buffer[static_cast<size_t>(((c * kSmall.frames + f) * kSmall.height + y) * kSmall.width + x)],
                              sample_value(f, y, x, c));
}

TEST(Sequence, FramesInAndOutOfStridedMemory) {
    // Every other pixel of a wider buffer: the odd pixels must never be touched.
    const Shape s{2, 3, 4, 3};
    const float sentinel = -12345.0f;
    std::vector<float> buffer(static_cast<size_t>(s.samples() * 2), sentinel);
    Strides st;
    st.channel = kF;
    st.pixel = 2 * s.channels * kF;
    st.row = st.pixel * s.width;
    st.frame = st.row * s.height;
    Sequence seq(buffer.data(), s, st);

    Sequence source(s);
    fill(source);
    std::vector<float> frame(static_cast<size_t>(s.pixels() * s.channels));
    for (int64_t f = 0; f < s.frames; ++f) {
        source.get_frame(f, frame.data());
        seq.set_frame(f, frame.data());
    }
    expect_samples(seq);
    for (size_t i = 0; i < buffer.size(); ++i)
        if ((i / static_cast<size_t>(s.channels)) % 2 == 1) {
            ASSERT_EQ(buffer[i], sentinel) << "gap sample " << i;
        }

    std::vector<float> out(frame.size());
    seq.get_frame(1, out.data());
    source.get_frame(1, frame.data());
    EXPECT_EQ(out, frame);
}

TEST(Sequence, CopySamplesBetweenLayouts) {
    Sequence contiguous(kSmall);
    fill(contiguous);
    std::vector<float> planar(static_cast<size_t>(kSmall.samples()), -1.0f);
    Sequence wrapped(planar.data(), kSmall, planar_strides(kSmall));
    wrapped.copy_samples_from(contiguous);
    expect_samples(wrapped);

    Sequence back(kSmall);
    back.copy_samples_from(wrapped);
    expect_samples(back);

    Sequence other(Shape{3, 4, 5, 3});
    EXPECT_EQ(status_of([&] { other.copy_samples_from(contiguous); }), Status::InvalidArgument);
}

TEST(Sequence, RejectsMisalignedOrNegativeStrides) {
    std::vector<float> buffer(static_cast<size_t>(kSmall.samples()) + 8);
    const Strides good = contiguous_strides(kSmall);
    auto with = [&](int64_t Strides::*member, int64_t value) {
        Strides st = good;
        st.*member = value;
        return st;
    };
    for (auto member : {&Strides::channel, &Strides::pixel, &Strides::row, &Strides::frame}) {
        EXPECT_EQ(status_of([&] { Sequence(buffer.data(), kSmall, with(member, (good.*member) + 2)); }),
                  Status::InvalidArgument);
        EXPECT_EQ(status_of([&] { Sequence(buffer.data(), kSmall, with(member, -(good.*member))); }),
                  Status::InvalidArgument);
    }
    EXPECT_EQ(status_of([&] { Sequence(nullptr, kSmall, good); }), Status::InvalidArgument);
    // Data not aligned to a float.
    float* odd = reinterpret_cast<float*>(reinterpret_cast<char*>(buffer.data()) + 2);
    EXPECT_EQ(status_of([&] { Sequence(odd, kSmall, good); }), Status::InvalidArgument);
    // Zero strides (broadcasting one value) are allowed.
    EXPECT_EQ(status_of([&] { Sequence(buffer.data(), kSmall, Strides{0, 0, 0, 0}); }), Status::Ok);
}

TEST(Sequence, CopyAttributes) {
    Sequence a(kSmall), b(kSmall);
    a.channel_names() = {"R", "G"};
    a.frame_numbers() = {10, 11, 12};
    a.metadata()[2].attribute("studio:shot", "sh010");
    b.copy_attributes_from(a);
    EXPECT_EQ(b.channel_names(), a.channel_names());
    EXPECT_EQ(b.frame_numbers(), a.frame_numbers());
    EXPECT_EQ(b.metadata()[2].get_string("studio:shot"), "sh010");
    Sequence c(Shape{2, 4, 5, 2});
    EXPECT_EQ(status_of([&] { c.copy_attributes_from(a); }), Status::InvalidArgument);
}

TEST(ChannelStats, CountsNanAndInfAndSkipsThemInMinMaxMean) {
    Sequence seq(Shape{2, 1, 3, 2});
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    // Channel 0: 1, 2, NaN, -4, inf, -inf. Channel 1 all 5.
    const float c0[] = {1, 2, nan, -4, inf, -inf};
    for (int i = 0; i < 6; ++i) {
        seq.at(i / 3, 0, i % 3, 0) = c0[i];
        seq.at(i / 3, 0, i % 3, 1) = 5;
    }
    const ChannelStats st = channel_stats(seq, 0);
    EXPECT_EQ(st.nan_count, 1);
    EXPECT_EQ(st.inf_count, 2);
    EXPECT_DOUBLE_EQ(st.min, -4);
    EXPECT_DOUBLE_EQ(st.max, 2);
    EXPECT_DOUBLE_EQ(st.mean, -1.0 / 3.0);
    const ChannelStats st1 = channel_stats(seq, 1);
    EXPECT_EQ(st1.nan_count + st1.inf_count, 0);
    EXPECT_DOUBLE_EQ(st1.mean, 5);
    EXPECT_EQ(status_of([&] { channel_stats(seq, 2); }), Status::InvalidArgument);
    EXPECT_EQ(status_of([&] { channel_stats(seq, -1); }), Status::InvalidArgument);
}

TEST(ChannelStats, AllNonFiniteGivesZeros) {
    Sequence seq(Shape{1, 1, 2, 1});
    seq.at(0, 0, 0, 0) = std::numeric_limits<float>::quiet_NaN();
    seq.at(0, 0, 1, 0) = std::numeric_limits<float>::infinity();
    const ChannelStats st = channel_stats(seq, 0);
    EXPECT_EQ(st.min, 0);
    EXPECT_EQ(st.max, 0);
    EXPECT_EQ(st.mean, 0);
    EXPECT_EQ(st.nan_count, 1);
    EXPECT_EQ(st.inf_count, 1);
}
