// The C ABI as a C program sees it: versions, status codes, NULL handling, shape and stride
// validation, versioned option structs, filters, callbacks and the thread-local error message.
#include <statfilter/statfilter.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <thread>

#include "capi_util.hpp"

using namespace statfilter_test;

namespace {

constexpr int64_t kF = sizeof(float);
const sf_shape kShape = shape_of(3, 4, 5, 2);

// Channel-planar strides (channel, frame, row, pixel).
sf_strides planar(const sf_shape& s) {
    const int64_t frame = kF * s.width * s.height;
    return sf_strides{frame * s.frames, kF, kF * s.width, frame};
}

// Every other pixel of a buffer twice as wide.
sf_strides every_other_pixel(const sf_shape& s) {
    const int64_t pixel = 2 * kF * s.channels;
    return sf_strides{kF, pixel, pixel * s.width, pixel * s.width * s.height};
}

}  // namespace

// ---- version and status ---------------------------------------------------------------------

TEST(Version, MatchesTheHeader) {
    EXPECT_EQ(sf_version(), SF_VERSION);
    EXPECT_EQ(SF_VERSION, SF_VERSION_MAJOR * 10000 + SF_VERSION_MINOR * 100 + SF_VERSION_PATCH);
    const std::string text = std::to_string(SF_VERSION_MAJOR) + "." + std::to_string(SF_VERSION_MINOR) + "." +
                             std::to_string(SF_VERSION_PATCH);
    EXPECT_EQ(std::string(sf_version_string()), text);
}

TEST(Status, Names) {
    const std::pair<sf_status, const char*> names[] = {
        {SF_OK, "SF_OK"},
        {SF_ERROR_INVALID_ARGUMENT, "SF_ERROR_INVALID_ARGUMENT"},
        {SF_ERROR_OUT_OF_MEMORY, "SF_ERROR_OUT_OF_MEMORY"},
        {SF_ERROR_IO, "SF_ERROR_IO"},
        {SF_ERROR_NOT_FOUND, "SF_ERROR_NOT_FOUND"},
        {SF_ERROR_UNSUPPORTED, "SF_ERROR_UNSUPPORTED"},
        {SF_ERROR_CANCELLED, "SF_ERROR_CANCELLED"},
        {SF_ERROR_NUMERIC, "SF_ERROR_NUMERIC"},
        {SF_ERROR_INTERNAL, "SF_ERROR_INTERNAL"},
    };
    for (const auto& [status, name] : names) EXPECT_STREQ(sf_status_name(status), name);
    EXPECT_STREQ(sf_status_name(static_cast<sf_status>(99)), "SF_ERROR_UNKNOWN");
    EXPECT_STREQ(sf_status_name(static_cast<sf_status>(-1)), "SF_ERROR_UNKNOWN");
}

// ---- shapes ------------------------------------------------------------------------------------

TEST(CapiShape, CreateIsZeroedContiguousAndNamed) {
    Seq seq = create_sequence(kShape);
    ASSERT_TRUE(seq);
    sf_shape shape{};
    EXPECT_SF_OK(sf_sequence_shape(seq.get(), &shape));
    EXPECT_EQ(std::memcmp(&shape, &kShape, sizeof shape), 0);
    float* data = nullptr;
    sf_strides st{};
    EXPECT_SF_OK(sf_sequence_data(seq.get(), &data, &st));
    const sf_strides expected = contiguous(kShape);
    EXPECT_EQ(std::memcmp(&st, &expected, sizeof st), 0);
    for (int64_t i = 0; i < sample_count(kShape); ++i) ASSERT_EQ(data[i], 0.0f);
    EXPECT_EQ(channel_name(seq.get(), 1), "C1");
    EXPECT_EQ(frame_numbers(seq.get()), (std::vector<int64_t>{1, 2, 3}));
}

TEST(CapiShape, ZeroOrNegativeDimensionsRejected) {
    for (const sf_shape& s : {shape_of(0, 4, 4, 1), shape_of(1, 0, 4, 1), shape_of(1, 4, 0, 1), shape_of(1, 4, 4, 0),
                              shape_of(-2, 4, 4, 1), shape_of(1, -1, 4, 1), shape_of(1, 4, -7, 1),
                              shape_of(1, 4, 4, -1)}) {
        int dummy = 0;
        sf_sequence out = reinterpret_cast<sf_sequence>(&dummy);  // must be reset to NULL
        expect_failure(sf_sequence_create(s, &out), SF_ERROR_INVALID_ARGUMENT, {">= 1"});
        EXPECT_EQ(out, nullptr);
    }
}

TEST(CapiShape, FramesBeyond32BitPixelCountsRejectedBeforeAllocating) {
    // 65536 x 65536 is 2^32 pixels (16 GiB of floats): rejected as an argument, never attempted
    // (an attempt would return OK or SF_ERROR_OUT_OF_MEMORY after touching the memory).
    sf_sequence out = nullptr;
    expect_failure(sf_sequence_create(shape_of(1, 65536, 65536, 1), &out), SF_ERROR_INVALID_ARGUMENT,
                   {"65536 x 65536", "2^31 - 1"});
    EXPECT_EQ(out, nullptr);
    expect_failure(sf_sequence_create(shape_of(1, 46341, 46341, 1), &out), SF_ERROR_INVALID_ARGUMENT, {"2^31 - 1"});
    // The same limit holds for wrapped memory, where nothing is allocated at all.
    float one = 0;
    expect_failure(sf_sequence_wrap(&one, shape_of(1, 65536, 65536, 1), sf_strides{0, 0, 0, 0}, &out),
                   SF_ERROR_INVALID_ARGUMENT, {"2^31 - 1"});
}

TEST(CapiShape, HugeFrameCountsRejected) {
    constexpr int64_t max = std::numeric_limits<int64_t>::max();
    sf_sequence out = nullptr;
    for (const sf_shape& s : {shape_of(max, 1, 1, 1), shape_of(max / 4, 1000, 1000, 1), shape_of(int64_t{1} << 40, 40000, 40000, 4),
                              shape_of(1, 2, 2, max)}) {
        expect_failure(sf_sequence_create(s, &out), SF_ERROR_INVALID_ARGUMENT, {"overflows"});
        EXPECT_EQ(out, nullptr);
    }
}

// ---- strided memory --------------------------------------------------------------------------

TEST(CapiStrides, PlanarWrapReadsTheRightSamples) {
    std::vector<float> planar_buffer(static_cast<size_t>(sample_count(kShape)));
    const sf_strides st = planar(kShape);
    for_each_sample(kShape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        *sample_at(planar_buffer.data(), st, f, y, x, c) = sample_value(f, y, x, c);
    });
    sf_sequence raw = nullptr;
    ASSERT_SF_OK(sf_sequence_wrap(planar_buffer.data(), kShape, st, &raw));
    Seq seq(raw);

    float* data = nullptr;
    sf_strides got{};
    EXPECT_SF_OK(sf_sequence_data(seq.get(), &data, &got));
    EXPECT_EQ(data, planar_buffer.data());  // borrowed, not copied
    EXPECT_EQ(std::memcmp(&got, &st, sizeof got), 0);

    const std::vector<float> out = samples_of(seq.get());
    size_t i = 0;
    for_each_sample(kShape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        ASSERT_EQ(out[i++], sample_value(f, y, x, c)) << f << "," << y << "," << x << "," << c;
    });
    // Statistics walk the same strides: channel 1 only.
    sf_channel_stats stats{};
    EXPECT_SF_OK(sf_sequence_channel_stats(seq.get(), 1, &stats));
    EXPECT_EQ(stats.min, sample_value(0, 0, 0, 1));
    EXPECT_EQ(stats.max, sample_value(2, 3, 4, 1));
}

TEST(CapiStrides, CopyToOtherStridesLeavesTheGapsAlone) {
    Seq seq = filled_sequence(kShape);
    const float sentinel = -999.0f;
    std::vector<float> wide(static_cast<size_t>(sample_count(kShape) * 2), sentinel);
    const sf_strides st = every_other_pixel(kShape);
    ASSERT_SF_OK(sf_sequence_copy_to(seq.get(), wide.data(), st));
    for_each_sample(kShape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        ASSERT_EQ(*sample_at(wide.data(), st, f, y, x, c), sample_value(f, y, x, c));
        // The pixel after each written one is a gap.
        ASSERT_EQ(*sample_at(wide.data(), st, f, y, x, c + kShape.channels), sentinel);
    });

    std::vector<float> planar_out(static_cast<size_t>(sample_count(kShape)));
    ASSERT_SF_OK(sf_sequence_copy_to(seq.get(), planar_out.data(), planar(kShape)));
    EXPECT_EQ(planar_out[static_cast<size_t>(sample_count(kShape) / 2)], sample_value(0, 0, 0, 1));
}

TEST(CapiStrides, FilterWritesIntoStridedOutput) {
    Seq input = filled_sequence(kShape);
    const float sentinel = 1234.5f;
    std::vector<float> wide(static_cast<size_t>(sample_count(kShape) * 2), sentinel);
    const sf_strides st = every_other_pixel(kShape);
    sf_sequence raw = nullptr;
    ASSERT_SF_OK(sf_sequence_wrap(wide.data(), kShape, st, &raw));
    Seq output(raw);
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    ASSERT_SF_OK(sf_filter_execute(filter.get(), input.get(), output.get()));
    for_each_sample(kShape, [&](int64_t fr, int64_t y, int64_t x, int64_t c) {
        ASSERT_EQ(*sample_at(wide.data(), st, fr, y, x, c), sample_value(fr, y, x, c));
        ASSERT_EQ(*sample_at(wide.data(), st, fr, y, x, c + kShape.channels), sentinel);
    });
}

TEST(CapiStrides, MisalignedOrNegativeStridesRejected) {
    std::vector<float> buffer(static_cast<size_t>(sample_count(kShape)) * 2);
    Seq seq = filled_sequence(kShape);
    const sf_strides good = contiguous(kShape);
    for (int member = 0; member < 4; ++member) {
        for (int64_t delta : {int64_t{2}, int64_t{1}, int64_t{-1000}}) {
            sf_strides bad = good;
            int64_t* field[] = {&bad.channel, &bad.pixel, &bad.row, &bad.frame};
            *field[member] += delta;
            sf_sequence out = nullptr;
            expect_failure(sf_sequence_wrap(buffer.data(), kShape, bad, &out), SF_ERROR_INVALID_ARGUMENT,
                           {"multiples of 4"}, "wrap");
            EXPECT_EQ(out, nullptr);
            const std::vector<float> before = buffer;
            expect_failure(sf_sequence_copy_to(seq.get(), buffer.data(), bad), SF_ERROR_INVALID_ARGUMENT,
                           {"multiples of 4"}, "copy_to");
            EXPECT_EQ(buffer, before);  // nothing written
        }
    }
}

// Checked before the library touches the pointer (UBSan: no reference bound to a misaligned float).
TEST(CapiStrides, MisalignedDataRejected) {
    std::vector<float> buffer(static_cast<size_t>(sample_count(kShape)) + 1);
    float* misaligned = reinterpret_cast<float*>(reinterpret_cast<char*>(buffer.data()) + 1);
    sf_sequence out = nullptr;
    expect_failure(sf_sequence_wrap(misaligned, kShape, contiguous(kShape), &out), SF_ERROR_INVALID_ARGUMENT,
                   {"'data'", "aligned"}, "wrap");
    EXPECT_EQ(out, nullptr);
    Seq seq = filled_sequence(kShape);
    expect_failure(sf_sequence_copy_to(seq.get(), misaligned, contiguous(kShape)), SF_ERROR_INVALID_ARGUMENT,
                   {"'dst'", "aligned"}, "copy_to");
}

// ---- names and numbers -----------------------------------------------------------------------

TEST(CapiSequence, ChannelNamesAndFrameNumbers) {
    Seq seq = create_sequence(kShape);
    EXPECT_SF_OK(sf_sequence_set_channel_name(seq.get(), 0, "albedo.R"));
    EXPECT_EQ(channel_name(seq.get(), 0), "albedo.R");
    EXPECT_SF_OK(sf_sequence_set_frame_number(seq.get(), 2, -17));
    EXPECT_EQ(frame_numbers(seq.get()), (std::vector<int64_t>{1, 2, -17}));

    const char* name = nullptr;
    int64_t number = 0;
    expect_failure(sf_sequence_channel_name(seq.get(), 2, &name), SF_ERROR_INVALID_ARGUMENT, {"channel index 2"});
    expect_failure(sf_sequence_channel_name(seq.get(), -1, &name), SF_ERROR_INVALID_ARGUMENT, {"channel index -1"});
    expect_failure(sf_sequence_set_channel_name(seq.get(), 0, ""), SF_ERROR_INVALID_ARGUMENT, {"empty"});
    expect_failure(sf_sequence_frame_number(seq.get(), 3, &number), SF_ERROR_INVALID_ARGUMENT, {"frame index 3"});
    expect_failure(sf_sequence_set_frame_number(seq.get(), -1, 5), SF_ERROR_INVALID_ARGUMENT, {"frame index -1"});
    sf_channel_stats stats;
    expect_failure(sf_sequence_channel_stats(seq.get(), 2, &stats), SF_ERROR_INVALID_ARGUMENT, {"channel index 2"});
    EXPECT_EQ(channel_name(seq.get(), 0), "albedo.R");  // unchanged by the failures
}

// ---- NULL arguments --------------------------------------------------------------------------

namespace {

struct NullCase {
    const char* call;
    const char* argument;  // the name the message must quote
    std::function<sf_status()> run;
};

int ignore_progress(void*, double, const char*) { return 0; }

}  // namespace

TEST(CapiNull, EveryPointerArgumentIsChecked) {
    Seq seq = create_sequence(kShape);
    Seq other = create_sequence(kShape);
    sf_filter fh = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &fh));
    Filt filter(fh);
    sf_sequence s = seq.get();
    sf_filter f = filter.get();

    sf_sequence out_seq = nullptr;
    sf_filter out_filter = nullptr;
    sf_shape shape{};
    sf_strides strides = contiguous(kShape);
    float* data = nullptr;
    std::vector<float> buffer(static_cast<size_t>(sample_count(kShape)));
    const char* text = nullptr;
    int64_t number = 0;
    int count = 0;
    double value = 0;
    size_t size = 0;
    char chars[64];
    sf_channel_stats stats{};
    sf_param_info info{};
    info.struct_size = sizeof info;
    sf_read_options ro;
    sf_read_options_init(&ro);
    sf_write_options wo;
    sf_write_options_init(&wo);
    int64_t frames[4];
    sf_comparison comparison;
    sf_comparison_init(&comparison);

    const std::vector<NullCase> cases = {
        {"sf_sequence_create", "out", [&] { return sf_sequence_create(kShape, nullptr); }},
        {"sf_sequence_wrap", "data", [&] { return sf_sequence_wrap(nullptr, kShape, strides, &out_seq); }},
        {"sf_sequence_wrap", "out", [&] { return sf_sequence_wrap(buffer.data(), kShape, strides, nullptr); }},
        {"sf_sequence_shape", "sequence", [&] { return sf_sequence_shape(nullptr, &shape); }},
        {"sf_sequence_shape", "out", [&] { return sf_sequence_shape(s, nullptr); }},
        {"sf_sequence_data", "sequence", [&] { return sf_sequence_data(nullptr, &data, &strides); }},
        {"sf_sequence_data", "data", [&] { return sf_sequence_data(s, nullptr, &strides); }},
        {"sf_sequence_copy_to", "sequence", [&] { return sf_sequence_copy_to(nullptr, buffer.data(), strides); }},
        {"sf_sequence_copy_to", "dst", [&] { return sf_sequence_copy_to(s, nullptr, strides); }},
        {"sf_sequence_channel_name", "sequence", [&] { return sf_sequence_channel_name(nullptr, 0, &text); }},
        {"sf_sequence_channel_name", "name", [&] { return sf_sequence_channel_name(s, 0, nullptr); }},
        {"sf_sequence_set_channel_name", "sequence", [&] { return sf_sequence_set_channel_name(nullptr, 0, "R"); }},
        {"sf_sequence_set_channel_name", "name", [&] { return sf_sequence_set_channel_name(s, 0, nullptr); }},
        {"sf_sequence_frame_number", "sequence", [&] { return sf_sequence_frame_number(nullptr, 0, &number); }},
        {"sf_sequence_frame_number", "number", [&] { return sf_sequence_frame_number(s, 0, nullptr); }},
        {"sf_sequence_set_frame_number", "sequence", [&] { return sf_sequence_set_frame_number(nullptr, 0, 1); }},
        {"sf_sequence_channel_stats", "sequence", [&] { return sf_sequence_channel_stats(nullptr, 0, &stats); }},
        {"sf_sequence_channel_stats", "out", [&] { return sf_sequence_channel_stats(s, 0, nullptr); }},
        {"sf_pattern_frames", "pattern", [&] { return sf_pattern_frames(nullptr, frames, 4, &size); }},
        {"sf_pattern_frames", "count", [&] { return sf_pattern_frames("a.####.exr", frames, 4, nullptr); }},
        {"sf_pattern_format", "pattern", [&] { return sf_pattern_format(nullptr, 1, chars, sizeof chars, &size); }},
        {"sf_pattern_format", "buffer", [&] { return sf_pattern_format("a.####.exr", 1, nullptr, 0, nullptr); }},
        {"sf_sequence_read", "pattern", [&] { return sf_sequence_read(nullptr, &ro, &out_seq); }},
        {"sf_sequence_read", "out", [&] { return sf_sequence_read("a.####.exr", &ro, nullptr); }},
        {"sf_sequence_write", "sequence", [&] { return sf_sequence_write(nullptr, "a.####.exr", &wo); }},
        {"sf_sequence_write", "pattern", [&] { return sf_sequence_write(s, nullptr, &wo); }},
        {"sf_filter_create", "name", [&] { return sf_filter_create(nullptr, &out_filter); }},
        {"sf_filter_create", "out", [&] { return sf_filter_create("copy", nullptr); }},
        {"sf_filter_set_int", "filter", [&] { return sf_filter_set_int(nullptr, "rank", 1); }},
        {"sf_filter_set_int", "name", [&] { return sf_filter_set_int(f, nullptr, 1); }},
        {"sf_filter_set_float", "filter", [&] { return sf_filter_set_float(nullptr, "sigma", 1); }},
        {"sf_filter_set_float", "name", [&] { return sf_filter_set_float(f, nullptr, 1); }},
        {"sf_filter_set_string", "filter", [&] { return sf_filter_set_string(nullptr, "rank", "auto"); }},
        {"sf_filter_set_string", "name", [&] { return sf_filter_set_string(f, nullptr, "auto"); }},
        {"sf_filter_set_string", "value", [&] { return sf_filter_set_string(f, "rank", nullptr); }},
        {"sf_filter_get_int", "filter", [&] { return sf_filter_get_int(nullptr, "rank", &number); }},
        {"sf_filter_get_int", "name", [&] { return sf_filter_get_int(f, nullptr, &number); }},
        {"sf_filter_get_int", "value", [&] { return sf_filter_get_int(f, "rank", nullptr); }},
        {"sf_filter_get_float", "filter", [&] { return sf_filter_get_float(nullptr, "sigma", &value); }},
        {"sf_filter_get_float", "name", [&] { return sf_filter_get_float(f, nullptr, &value); }},
        {"sf_filter_get_float", "value", [&] { return sf_filter_get_float(f, "sigma", nullptr); }},
        {"sf_filter_get_string", "filter", [&] { return sf_filter_get_string(nullptr, "rank", &text); }},
        {"sf_filter_get_string", "name", [&] { return sf_filter_get_string(f, nullptr, &text); }},
        {"sf_filter_get_string", "value", [&] { return sf_filter_get_string(f, "rank", nullptr); }},
        {"sf_filter_param_count", "filter", [&] { return sf_filter_param_count(nullptr, &count); }},
        {"sf_filter_param_count", "count", [&] { return sf_filter_param_count(f, nullptr); }},
        {"sf_filter_param_info", "filter", [&] { return sf_filter_param_info(nullptr, 0, &info); }},
        {"sf_filter_param_info", "info", [&] { return sf_filter_param_info(f, 0, nullptr); }},
        {"sf_filter_result_count", "filter", [&] { return sf_filter_result_count(nullptr, &count); }},
        {"sf_filter_result_count", "count", [&] { return sf_filter_result_count(f, nullptr); }},
        {"sf_filter_result_name", "filter", [&] { return sf_filter_result_name(nullptr, 0, &text); }},
        {"sf_filter_result_name", "name", [&] { return sf_filter_result_name(f, 0, nullptr); }},
        {"sf_filter_result_float", "filter", [&] { return sf_filter_result_float(nullptr, "rank", &value); }},
        {"sf_filter_result_float", "name", [&] { return sf_filter_result_float(f, nullptr, &value); }},
        {"sf_filter_result_float", "value", [&] { return sf_filter_result_float(f, "rank", nullptr); }},
        {"sf_filter_result_string", "filter", [&] { return sf_filter_result_string(nullptr, "rank", &text); }},
        {"sf_filter_result_string", "name", [&] { return sf_filter_result_string(f, nullptr, &text); }},
        {"sf_filter_result_string", "value", [&] { return sf_filter_result_string(f, "rank", nullptr); }},
        {"sf_filter_result_sequence", "filter", [&] { return sf_filter_result_sequence(nullptr, "rank_map", &out_seq); }},
        {"sf_filter_result_sequence", "name", [&] { return sf_filter_result_sequence(f, nullptr, &out_seq); }},
        {"sf_filter_result_sequence", "out", [&] { return sf_filter_result_sequence(f, "rank_map", nullptr); }},
        {"sf_sequence_compare", "test", [&] { return sf_sequence_compare(nullptr, s, &comparison); }},
        {"sf_sequence_compare", "reference", [&] { return sf_sequence_compare(s, nullptr, &comparison); }},
        {"sf_sequence_compare", "out", [&] { return sf_sequence_compare(s, other.get(), nullptr); }},
        {"sf_filter_set_progress", "filter", [&] { return sf_filter_set_progress(nullptr, ignore_progress, nullptr); }},
        {"sf_filter_execute", "filter", [&] { return sf_filter_execute(nullptr, s, other.get()); }},
        {"sf_filter_execute", "input", [&] { return sf_filter_execute(f, nullptr, other.get()); }},
        {"sf_filter_execute", "output", [&] { return sf_filter_execute(f, s, nullptr); }},
    };
    for (const NullCase& c : cases) {
        const std::string what = std::string(c.call) + " with NULL " + c.argument;
        expect_failure(c.run(), SF_ERROR_INVALID_ARGUMENT, {std::string("'") + c.argument + "'"}, what.c_str());
    }
    // Failures on a filter are also readable from the handle.
    expect_failure(sf_filter_get_int(f, "rank", nullptr), SF_ERROR_INVALID_ARGUMENT, {"'value'"});
    EXPECT_STREQ(sf_filter_last_error(f), sf_last_error());
    // Nothing was created by any of the failed calls.
    EXPECT_EQ(out_seq, nullptr);
    EXPECT_EQ(out_filter, nullptr);
}

TEST(CapiNull, ReleasingAndOptionalPointers) {
    EXPECT_EQ(sf_sequence_release(nullptr), SF_OK);
    EXPECT_EQ(sf_filter_release(nullptr), SF_OK);
    sf_read_options_init(nullptr);
    sf_write_options_init(nullptr);
    sf_comparison_init(nullptr);
    EXPECT_STREQ(sf_filter_last_error(nullptr), "");
    EXPECT_EQ(sf_filter_description(nullptr), nullptr);
    EXPECT_EQ(sf_filter_name(-1), nullptr);
    EXPECT_EQ(sf_filter_name(sf_filter_count()), nullptr);
    sf_set_error_callback(nullptr, nullptr);

    // Documented as optional: the strides of sf_sequence_data, `needed` when a buffer is given,
    // the options structs (defaults), and a NULL progress callback.
    Seq seq = create_sequence(kShape);
    float* data = nullptr;
    EXPECT_SF_OK(sf_sequence_data(seq.get(), &data, nullptr));
    EXPECT_NE(data, nullptr);
    char name[32];
    EXPECT_SF_OK(sf_pattern_format("a.####.exr", 12, name, sizeof name, nullptr));
    EXPECT_STREQ(name, "a.0012.exr");
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    EXPECT_SF_OK(sf_filter_set_progress(f, nullptr, nullptr));
    TempDir dir;
    EXPECT_SF_OK(sf_sequence_write(seq.get(), dir.file("d.####.exr").c_str(), nullptr));
    sf_sequence back = nullptr;
    EXPECT_SF_OK(sf_sequence_read(dir.file("d.####.exr").c_str(), nullptr, &back));
    Seq owned(back);
    EXPECT_EQ(frame_numbers(back), (std::vector<int64_t>{1, 2, 3}));
}

// ---- patterns ----------------------------------------------------------------------------------

TEST(CapiPattern, FormatTwoCallIdiom) {
    size_t needed = 0;
    ASSERT_SF_OK(sf_pattern_format("dir/a.%04d.exr", 42, nullptr, 0, &needed));
    EXPECT_EQ(needed, std::strlen("dir/a.0042.exr") + 1);
    std::vector<char> buffer(needed);
    ASSERT_SF_OK(sf_pattern_format("dir/a.%04d.exr", 42, buffer.data(), buffer.size(), &needed));
    EXPECT_STREQ(buffer.data(), "dir/a.0042.exr");
    expect_failure(sf_pattern_format("dir/a.%04d.exr", 42, buffer.data(), needed - 1, &needed),
                   SF_ERROR_INVALID_ARGUMENT, {"too small"});
    expect_failure(sf_pattern_format("", 1, buffer.data(), buffer.size(), &needed), SF_ERROR_INVALID_ARGUMENT,
                   {"pattern"});
}

TEST(CapiPattern, FramesTwoCallIdiom) {
    TempDir dir;
    Seq seq = filled_sequence(shape_of(3, 2, 2, 1));
    for (int64_t i = 0; i < 3; ++i) ASSERT_SF_OK(sf_sequence_set_frame_number(seq.get(), i, 9 + i * i));
    sf_write_options o = write_options();
    ASSERT_SF_OK(sf_sequence_write(seq.get(), dir.file("p.#.exr").c_str(), &o));
    const std::string pattern = dir.file("p.%04d.exr");
    size_t count = 0;
    ASSERT_SF_OK(sf_pattern_frames(pattern.c_str(), nullptr, 0, &count));
    EXPECT_EQ(count, 3u);
    int64_t numbers[3] = {0, 0, 0};
    ASSERT_SF_OK(sf_pattern_frames(pattern.c_str(), numbers, 2, &count));
    EXPECT_EQ(count, 2u);
    EXPECT_EQ(numbers[0], 9);
    EXPECT_EQ(numbers[1], 10);
    EXPECT_EQ(numbers[2], 0);  // beyond capacity: untouched
    expect_failure(sf_pattern_frames(dir.file("q.####.exr").c_str(), numbers, 3, &count), SF_ERROR_NOT_FOUND,
                   {"q.####.exr"});
    EXPECT_EQ(count, 0u);
}

// ---- versioned option structs ----------------------------------------------------------------

TEST(CapiOptions, InitFillsDefaults) {
    sf_write_options w;
    std::memset(&w, 0xAB, sizeof w);
    sf_write_options_init(&w);
    EXPECT_EQ(w.struct_size, sizeof(sf_write_options));
    EXPECT_EQ(w.pixel_type, SF_PIXEL_HALF);
    EXPECT_STREQ(w.compression, "zip");
    EXPECT_EQ(w.half_overflow, 0);
    EXPECT_EQ(w.progress, nullptr);
    sf_read_options r;
    std::memset(&r, 0xAB, sizeof r);
    sf_read_options_init(&r);
    EXPECT_EQ(r.struct_size, sizeof(sf_read_options));
    EXPECT_EQ(r.channels, nullptr);
    EXPECT_EQ(r.frames, nullptr);
    EXPECT_EQ(r.progress, nullptr);
}

TEST(CapiOptions, WrongStructSizesRejected) {
    TempDir dir;
    Seq seq = filled_sequence(kShape);
    const std::string pattern = dir.file("o.####.exr");
    struct {
        sf_write_options options;
        char newer_fields[64];
    } big_write{};
    sf_write_options_init(&big_write.options);
    struct {
        sf_read_options options;
        char newer_fields[64];
    } big_read{};
    sf_read_options_init(&big_read.options);

    for (size_t size : {size_t{0}, size_t{4}, sizeof(sf_write_options) + 8}) {
        big_write.options.struct_size = size;
        expect_failure(sf_sequence_write(seq.get(), pattern.c_str(), &big_write.options), SF_ERROR_INVALID_ARGUMENT,
                       {"struct_size", std::to_string(size)});
        EXPECT_TRUE(files_in(dir.path()).empty());
    }
    sf_write_options ok = write_options();
    ASSERT_SF_OK(sf_sequence_write(seq.get(), pattern.c_str(), &ok));
    for (size_t size : {size_t{0}, size_t{4}, sizeof(sf_read_options) + 8}) {
        big_read.options.struct_size = size;
        sf_sequence out = nullptr;
        expect_failure(sf_sequence_read(pattern.c_str(), &big_read.options, &out), SF_ERROR_INVALID_ARGUMENT,
                       {"struct_size"});
        EXPECT_EQ(out, nullptr);
    }
    // sf_param_info is versioned the same way.
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    struct {
        sf_param_info info;
        char newer_fields[64];
    } big_info{};
    for (size_t size : {size_t{0}, sizeof(sf_param_info) + 8}) {
        big_info.info.struct_size = size;
        expect_failure(sf_filter_param_info(f, 0, &big_info.info), SF_ERROR_INVALID_ARGUMENT, {"struct_size"});
    }
}

TEST(CapiOptions, OlderSmallerStructsAreAccepted) {
    TempDir dir;
    // A value only float can hold: a half write would fail with SF_ERROR_NUMERIC.
    Seq seq = filled_sequence(kShape, [](int64_t f, int64_t y, int64_t x, int64_t c) {
        return sample_value(f, y, x, c) * 1e6f;
    });
    const std::string pattern = dir.file("old.####.exr");

    // A caller built against a version whose struct ended after pixel_type.
    sf_write_options w;
    sf_write_options_init(&w);
    w.pixel_type = SF_PIXEL_FLOAT;
    w.compression = "no-such-compression";  // beyond the old size: must not be read
    w.struct_size = offsetof(sf_write_options, compression);
    ASSERT_SF_OK(sf_sequence_write(seq.get(), pattern.c_str(), &w));

    sf_read_options r;
    sf_read_options_init(&r);
    r.channels = "C1";
    r.frames = "no-such-frames";  // beyond the old size
    r.struct_size = offsetof(sf_read_options, frames);
    sf_sequence back = nullptr;
    ASSERT_SF_OK(sf_sequence_read(pattern.c_str(), &r, &back));
    Seq owned(back);
    sf_shape shape{};
    ASSERT_SF_OK(sf_sequence_shape(back, &shape));
    EXPECT_EQ(shape.channels, 1);
    EXPECT_EQ(shape.frames, 3);
    EXPECT_EQ(channel_name(back, 0), "C1");
    EXPECT_EQ(samples_of(back)[0], sample_value(0, 0, 0, 1) * 1e6f);  // written as float, exactly
}

// ---- filters ------------------------------------------------------------------------------------

TEST(CapiFilter, RegistryListsCopy) {
    ASSERT_GE(sf_filter_count(), 1);
    bool found = false;
    for (int i = 0; i < sf_filter_count(); ++i) {
        const char* name = sf_filter_name(i);
        ASSERT_NE(name, nullptr);
        ASSERT_NE(sf_filter_description(name), nullptr) << name;
        found = found || std::string(name) == "copy";
    }
    EXPECT_TRUE(found);
    EXPECT_EQ(sf_filter_description("no-such-filter"), nullptr);
}

TEST(CapiFilter, CreateCopyAndUnknownName) {
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    EXPECT_NE(f, nullptr);
    EXPECT_STREQ(sf_last_error(), "");
    int count = -1;
    EXPECT_SF_OK(sf_filter_param_count(f, &count));
    EXPECT_EQ(count, 0);
    EXPECT_SF_OK(sf_filter_result_count(f, &count));
    EXPECT_EQ(count, 0);

    sf_filter unknown = reinterpret_cast<sf_filter>(&count);  // must be reset to NULL
    expect_failure(sf_filter_create("pca-nonexistent", &unknown), SF_ERROR_NOT_FOUND, {"pca-nonexistent", "copy"});
    EXPECT_EQ(unknown, nullptr);
}

TEST(CapiFilter, UnknownParametersAndResults) {
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    int64_t i = 0;
    double d = 0;
    const char* s = nullptr;
    expect_failure(sf_filter_set_int(f, "rank", 3), SF_ERROR_NOT_FOUND, {"'rank'"});
    EXPECT_NE(std::string(sf_filter_last_error(f)).find("'rank'"), std::string::npos);
    expect_failure(sf_filter_set_float(f, "sigma", 1), SF_ERROR_NOT_FOUND, {"'sigma'"});
    expect_failure(sf_filter_set_string(f, "mode", "x"), SF_ERROR_NOT_FOUND, {"'mode'"});
    expect_failure(sf_filter_get_int(f, "rank", &i), SF_ERROR_NOT_FOUND, {"'rank'"});
    expect_failure(sf_filter_get_float(f, "rank", &d), SF_ERROR_NOT_FOUND, {"'rank'"});
    expect_failure(sf_filter_get_string(f, "rank", &s), SF_ERROR_NOT_FOUND, {"'rank'"});
    sf_param_info info{};
    info.struct_size = sizeof info;
    expect_failure(sf_filter_param_info(f, 0, &info), SF_ERROR_INVALID_ARGUMENT, {"index 0"});
    expect_failure(sf_filter_result_name(f, 0, &s), SF_ERROR_INVALID_ARGUMENT, {"index 0"});
    expect_failure(sf_filter_result_float(f, "rank", &d), SF_ERROR_NOT_FOUND, {"'rank'"});
    expect_failure(sf_filter_result_string(f, "rank", &s), SF_ERROR_NOT_FOUND, {"'rank'"});
}

TEST(CapiFilter, ParamInfoStringsStayValidWhileTheHandleLives) {
    // The header: strings returned as const char* stay valid until the owning handle is released.
    // So the infos of all parameters, taken one after another, must all still read correctly.
    int checked = 0;
    for (int k = 0; k < sf_filter_count(); ++k) {
        sf_filter f = nullptr;
        ASSERT_SF_OK(sf_filter_create(sf_filter_name(k), &f));
        Filt filter(f);
        int count = 0;
        ASSERT_SF_OK(sf_filter_param_count(f, &count));
        std::vector<sf_param_info> infos(static_cast<size_t>(count));
        std::vector<std::vector<std::string>> texts;
        for (int i = 0; i < count; ++i) {
            infos[i].struct_size = sizeof(sf_param_info);
            ASSERT_SF_OK(sf_filter_param_info(f, i, &infos[i]));
            texts.push_back({infos[i].name, infos[i].default_value, infos[i].description, infos[i].choices});
        }
        for (int i = 0; i < count; ++i) {
            const sf_param_info& info = infos[i];
            EXPECT_EQ((std::vector<std::string>{info.name, info.default_value, info.description, info.choices}),
                      texts[i])
                << sf_filter_name(k) << " parameter " << i;
            ++checked;
        }
    }
    if (checked == 0) GTEST_SKIP() << "no filter has parameters";
}

TEST(CapiFilter, MismatchedShapesRejected) {
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    Seq input = filled_sequence(kShape);
    for (const sf_shape& s : {shape_of(3, 4, 5, 3), shape_of(2, 4, 5, 2), shape_of(3, 5, 4, 2)}) {
        Seq output = create_sequence(s);
        expect_failure(sf_filter_execute(f, input.get(), output.get()), SF_ERROR_INVALID_ARGUMENT,
                       {"differs from input shape"});
        EXPECT_STREQ(sf_filter_last_error(f), sf_last_error());
        EXPECT_NE(std::string(sf_filter_last_error(f)).find("shape"), std::string::npos);
        for (float v : samples_of(output.get())) ASSERT_EQ(v, 0.0f);  // untouched
    }
}

TEST(CapiFilter, CopyIsBitExact) {
    const float nan_payload = [] {
        const uint32_t bits = 0x7FC12345u;
        float v;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }();
    const float specials[] = {-0.0f, std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max(),
                              -std::numeric_limits<float>::infinity(), nan_payload, 1e-30f, -1e30f};
    Seq input = filled_sequence(kShape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        const int64_t i = ((f * kShape.height + y) * kShape.width + x) * kShape.channels + c;
        return i % 10 < 7 ? specials[i % 10] : sample_value(f, y, x, c) / 3.0f;
    });
    // Output in a different layout, to exercise the strided path too.
    std::vector<float> planar_out(static_cast<size_t>(sample_count(kShape)));
    sf_sequence raw = nullptr;
    ASSERT_SF_OK(sf_sequence_wrap(planar_out.data(), kShape, planar(kShape), &raw));
    Seq output(raw);
    ASSERT_SF_OK(sf_sequence_set_channel_name(input.get(), 1, "Y"));
    ASSERT_SF_OK(sf_sequence_set_frame_number(input.get(), 0, 1001));
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    ASSERT_SF_OK(sf_filter_execute(f, input.get(), output.get()));

    const std::vector<float> a = samples_of(input.get()), b = samples_of(output.get());
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(float_bits(a[i]), float_bits(b[i])) << "sample " << i;
    EXPECT_EQ(channel_name(output.get(), 1), "Y");
    EXPECT_EQ(frame_numbers(output.get()).front(), 1001);

    // In place (same memory, same strides) is allowed.
    ASSERT_SF_OK(sf_filter_execute(f, input.get(), input.get()));
    EXPECT_EQ(samples_of(input.get()).size(), a.size());
}

// ---- callbacks -----------------------------------------------------------------------------------

namespace {

struct ProgressLog {
    std::vector<double> fractions;
    std::vector<std::string> stages;
    int cancel_at = -1;  // cancel on this call (0-based); -1 never
};

int record_progress(void* user, double fraction, const char* stage) {
    auto* log = static_cast<ProgressLog*>(user);
    log->fractions.push_back(fraction);
    log->stages.push_back(stage ? stage : "");
    return static_cast<int>(log->fractions.size()) - 1 == log->cancel_at;
}

}  // namespace

TEST(CapiProgress, FractionsInRangeAndCancel) {
    sf_filter f = nullptr;
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    Seq input = filled_sequence(kShape);
    Seq output = create_sequence(kShape);

    ProgressLog log;
    ASSERT_SF_OK(sf_filter_set_progress(f, record_progress, &log));
    ASSERT_SF_OK(sf_filter_execute(f, input.get(), output.get()));
    ASSERT_FALSE(log.fractions.empty());
    for (double v : log.fractions) EXPECT_TRUE(v >= 0.0 && v <= 1.0) << v;
    for (size_t i = 1; i < log.fractions.size(); ++i) EXPECT_GE(log.fractions[i], log.fractions[i - 1]);
    EXPECT_EQ(log.fractions.back(), 1.0);
    for (const std::string& stage : log.stages) EXPECT_FALSE(stage.empty());

    ProgressLog cancel;
    cancel.cancel_at = 0;
    Seq fresh = create_sequence(kShape);
    ASSERT_SF_OK(sf_filter_set_progress(f, record_progress, &cancel));
    expect_failure(sf_filter_execute(f, input.get(), fresh.get()), SF_ERROR_CANCELLED, {"cancel"});
    EXPECT_EQ(cancel.fractions.size(), 1u);  // no more calls after cancelling
    EXPECT_NE(std::string(sf_filter_last_error(f)).find("cancel"), std::string::npos);

    // Removing the callback: runs to completion again.
    ASSERT_SF_OK(sf_filter_set_progress(f, nullptr, nullptr));
    EXPECT_SF_OK(sf_filter_execute(f, input.get(), fresh.get()));
    EXPECT_EQ(samples_of(fresh.get()), samples_of(input.get()));
}

namespace {

struct ErrorLog {
    std::atomic<int> calls{0};
    sf_status status = SF_OK;
    std::string message;
};

void record_error(void* user, sf_status status, const char* message) {
    auto* log = static_cast<ErrorLog*>(user);
    log->status = status;
    log->message = message ? message : "";
    ++log->calls;
}

// Removes the error callback even when an assertion returns early.
struct ErrorCallbackScope {
    explicit ErrorCallbackScope(ErrorLog& log) { sf_set_error_callback(record_error, &log); }
    ~ErrorCallbackScope() { sf_set_error_callback(nullptr, nullptr); }
};

}  // namespace

TEST(CapiErrors, CallbackGetsStatusAndMessage) {
    ErrorLog log;
    {
        ErrorCallbackScope scope(log);
        sf_filter f = nullptr;
        EXPECT_EQ(sf_filter_create("no-such-filter", &f), SF_ERROR_NOT_FOUND);
        EXPECT_EQ(log.calls.load(), 1);
        EXPECT_EQ(log.status, SF_ERROR_NOT_FOUND);
        EXPECT_EQ(log.message, sf_last_error());
        EXPECT_NE(log.message.find("no-such-filter"), std::string::npos);

        // Success does not call it; failures on another thread do.
        ASSERT_SF_OK(sf_filter_create("copy", &f));
        sf_filter_release(f);
        EXPECT_EQ(log.calls.load(), 1);
        std::thread([] { sf_sequence_create(shape_of(0, 1, 1, 1), nullptr); }).join();
        EXPECT_EQ(log.calls.load(), 2);
        EXPECT_EQ(log.status, SF_ERROR_INVALID_ARGUMENT);
    }
    // Removed: no more calls.
    sf_sequence out = nullptr;
    EXPECT_NE(sf_sequence_create(shape_of(0, 1, 1, 1), &out), SF_OK);
    EXPECT_EQ(log.calls.load(), 2);
}

TEST(CapiErrors, LastErrorIsThreadLocalAndClearedBySuccess) {
    sf_filter f = nullptr;
    ASSERT_EQ(sf_filter_create("main-thread-filter", &f), SF_ERROR_NOT_FOUND);
    const std::string mine = sf_last_error();
    ASSERT_NE(mine.find("main-thread-filter"), std::string::npos);

    std::string theirs, theirs_after_success;
    std::thread other([&] {
        sf_filter g = nullptr;
        sf_filter_create("other-thread-filter", &g);
        theirs = sf_last_error();
        sf_filter_create("copy", &g);
        sf_filter_release(g);
        theirs_after_success = sf_last_error();
    });
    other.join();
    EXPECT_NE(theirs.find("other-thread-filter"), std::string::npos) << theirs;
    EXPECT_EQ(theirs_after_success, "");
    EXPECT_EQ(std::string(sf_last_error()), mine);  // untouched by the other thread

    // A successful call clears this thread's message.
    ASSERT_SF_OK(sf_filter_create("copy", &f));
    Filt filter(f);
    EXPECT_STREQ(sf_last_error(), "");
}

// The false-colour picture of an image result: the first channel of each frame, clamped to [0, 1]
// through the ramp (0 dark blue, 1 yellow), a NaN as 0; frame numbers kept, channels R, G, B.
TEST(CapiFalseColour, KnownColoursFrameNumbersAndChannels) {
    Seq image = filled_sequence(shape_of(2, 1, 4, 2), [](int64_t f, int64_t, int64_t x, int64_t c) {
        const float first[] = {0.0f, 1.0f, std::nanf(""), 0.5f};
        return c == 1 ? 99.0f : (f == 0 ? first[x] : -3.0f);  // the second channel is not looked at
    });
    ASSERT_SF_OK(sf_sequence_set_frame_number(image.get(), 0, 7));
    ASSERT_SF_OK(sf_sequence_set_frame_number(image.get(), 1, 9));
    sf_sequence out = nullptr;
    ASSERT_SF_OK(sf_sequence_false_colour(image.get(), &out));
    Seq rgb(out);
    sf_shape s{};
    ASSERT_SF_OK(sf_sequence_shape(rgb.get(), &s));
    EXPECT_EQ(s.frames, 2);
    EXPECT_EQ(s.width, 4);
    EXPECT_EQ(s.channels, 3);
    const std::vector<float> v = samples_of(rgb.get());
    const std::vector<float> blue = {0.0f, 0.15f, 0.55f}, yellow = {1.0f, 1.0f, 0.05f}, middle = {0.4f, 0.575f, 0.3f};
    const std::vector<std::vector<float>> expected = {blue, yellow, blue, middle, blue, blue, blue, blue};
    for (size_t p = 0; p < expected.size(); ++p)
        for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(v[p * 3 + c], expected[p][c], 1e-6) << p << " " << c;
    int64_t number = 0;
    ASSERT_SF_OK(sf_sequence_frame_number(rgb.get(), 1, &number));
    EXPECT_EQ(number, 9);
    const char* name = nullptr;
    ASSERT_SF_OK(sf_sequence_channel_name(rgb.get(), 2, &name));
    EXPECT_STREQ(name, "B");
    EXPECT_EQ(sf_sequence_false_colour(nullptr, &out), SF_ERROR_INVALID_ARGUMENT);
}

// Where an image result will go, checked before any work: the name, a frame token for a result with
// a frame per frame over more than one frame (one image needs none; the selection counts), the
// format, the directory, and never over an input frame on disk or an output frame of the run.
TEST(CapiImageOutput, CheckedBeforeAnyWorkAndNothingWritten) {
    TempDir dir;
    Seq frames = filled_sequence(shape_of(3, 2, 2, 1), [](int64_t, int64_t, int64_t, int64_t) { return 1.0f; });
    for (int64_t f = 0; f < 3; ++f) ASSERT_SF_OK(sf_sequence_set_frame_number(frames.get(), f, 1001 + f));
    const std::string in = dir.file("in/in.####.exr"), out = dir.file("out/o.####.exr");
    const sf_write_options wo = write_options(SF_PIXEL_FLOAT);
    ASSERT_SF_OK(sf_sequence_write(frames.get(), in.c_str(), &wo));
    sf_filter motion = nullptr;
    ASSERT_SF_OK(sf_filter_create("motion", &motion));
    Filt filter(motion);
    const auto check = [&](const char* name, const std::string& pattern, const char* selection = nullptr) {
        return sf_filter_check_image_output(motion, name, pattern.c_str(), in.c_str(), selection, out.c_str());
    };
    const auto refused = [&](const char* name, const std::string& pattern, const char* words, const char* selection = nullptr) {
        EXPECT_EQ(check(name, pattern, selection), SF_ERROR_INVALID_ARGUMENT) << pattern;
        EXPECT_NE(std::string(sf_filter_last_error(motion)).find(words), std::string::npos) << sf_filter_last_error(motion);
    };
    const std::string one = dir.file("maps/alpha.exr"), per_frame = dir.file("maps/beta.####.exr");
    EXPECT_SF_OK(check("alpha", one));  // one image: no token
    EXPECT_SF_OK(check("beta", per_frame));
    EXPECT_SF_OK(check("beta", one, "1002"));  // one frame selected: no token
    EXPECT_SF_OK(check("beta", dir.file("maps/b.png"), "1002,1002"));  // the same frame twice is one
    EXPECT_TRUE(fs::is_directory(dir.file("maps")));  // created, as for the run's output
    EXPECT_TRUE(fs::is_empty(dir.file("maps")));      // and nothing written in it
    refused("beta", one, "no frame token");
    refused("beta", one, "no frame token", "1001-1003x2");
    refused("rank_map", one, "it has: alpha, beta");
    refused("alpha", dir.file("in/in.1002.exr"), "is a frame of");        // an input frame by name
    refused("alpha", dir.file("in/../in/in.1003.exr"), "is a frame of");  // ... by another path to it
    refused("alpha", dir.file("out/o.1001.exr"), "is a frame of");        // a frame the run writes
    refused("beta", dir.file("in/in.####.exr"), "is a frame of");
    refused("alpha", dir.file("maps/alpha.xyz"), "no writer for its file format");
    write_text_file(dir.file("a_file"), "");
    EXPECT_NE(check("alpha", dir.file("a_file/alpha.exr")), SF_OK);
    refused("alpha", one, "invalid frame range", "5-");
    EXPECT_EQ(sf_filter_check_image_output(motion, nullptr, one.c_str(), in.c_str(), nullptr, nullptr),
              SF_ERROR_INVALID_ARGUMENT);
    EXPECT_SF_OK(sf_filter_check_image_output(motion, "alpha", one.c_str(), dir.file("none.####.exr").c_str(), nullptr,
                                              nullptr));  // no input on disk: the run says so, not this check
    EXPECT_TRUE(fs::is_empty(dir.file("maps")));
}
