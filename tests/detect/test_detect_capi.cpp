// Detection, the crop-window list and merge through the C ABI only.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <statfilter/statfilter.h>

namespace {

struct Owned {
    sf_sequence h = nullptr;
    ~Owned() { sf_sequence_release(h); }
};

// Contiguous (frame, row, pixel, channel) strides.
sf_strides strides_of(const sf_shape& s) {
    sf_strides st;
    st.channel = 4;
    st.pixel = 4 * s.channels;
    st.row = st.pixel * s.width;
    st.frame = st.row * s.height;
    return st;
}

struct Scene {
    sf_shape shape{16, 24, 32, 3};
    std::vector<float> noisy, denoised;
    Scene() {
        const size_t n = static_cast<size_t>(shape.frames * shape.height * shape.width * shape.channels);
        noisy.resize(n);
        denoised.resize(n);
        std::mt19937 rng(5);
        std::normal_distribution<float> normal;
        for (int64_t f = 0; f < shape.frames; ++f)
            for (int64_t y = 0; y < shape.height; ++y)
                for (int64_t x = 0; x < shape.width; ++x)
                    for (int64_t c = 0; c < 3; ++c) {
                        const size_t i = static_cast<size_t>(((f * shape.height + y) * shape.width + x) * 3 + c);
                        const float v = 0.6f + 0.2f * std::sin(x * 0.3f);
                        noisy[i] = v * (1 + 0.1f * normal(rng));
                        // The denoised result is wrong by 40% in a block of frames 6-8.
                        denoised[i] = v * ((f >= 6 && f <= 8 && y >= 4 && y < 12 && x >= 8 && x < 20) ? 1.4f : 1.0f);
                    }
    }
};

}  // namespace

TEST(DetectCapi, NamedInputResultsAndCropList) {
    Scene sc;
    Owned den, noisy, out;
    ASSERT_EQ(sf_sequence_wrap(sc.denoised.data(), sc.shape, strides_of(sc.shape), &den.h), SF_OK);
    ASSERT_EQ(sf_sequence_wrap(sc.noisy.data(), sc.shape, strides_of(sc.shape), &noisy.h), SF_OK);
    ASSERT_EQ(sf_sequence_create(sc.shape, &out.h), SF_OK);
    sf_filter f = nullptr;
    ASSERT_EQ(sf_filter_create("detect", &f), SF_OK);
    EXPECT_EQ(sf_filter_set_input(f, "albedo", noisy.h), SF_ERROR_NOT_FOUND);
    EXPECT_NE(std::string(sf_filter_last_error(f)).find("inputs: noisy"), std::string::npos) << sf_filter_last_error(f);
    EXPECT_EQ(sf_filter_set_input(nullptr, "noisy", noisy.h), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(sf_filter_set_input(f, nullptr, noisy.h), SF_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(sf_filter_set_input(f, "noisy", noisy.h), SF_OK);
    ASSERT_EQ(sf_filter_execute(f, den.h, out.h), SF_OK) << sf_filter_last_error(f);
    ASSERT_EQ(sf_filter_set_input(f, "noisy", nullptr), SF_OK);

    const char* source = nullptr;
    ASSERT_EQ(sf_filter_result_string(f, "source", &source), SF_OK);
    EXPECT_STREQ(source, "residual");
    double fraction = 0;
    ASSERT_EQ(sf_filter_result_float(f, "flagged_fraction", &fraction), SF_OK);
    const double block = 3.0 * 8 * 12 / (16.0 * 24 * 32);
    EXPECT_GT(fraction, 0.9 * block);
    EXPECT_LT(fraction, 2.0 * block);

    Owned mask;
    ASSERT_EQ(sf_filter_result_sequence(f, "mask", &mask.h), SF_OK);
    sf_shape ms;
    sf_sequence_shape(mask.h, &ms);
    EXPECT_EQ(ms.frames, 16);
    EXPECT_EQ(ms.channels, 1);
    // Nearly the whole block is flagged, and most flagged pixel-frames are the block's frames (a
    // polynomial that fits part of a 3-frame error rings into the frames next to it).
    float* m = nullptr;
    sf_strides mst;
    ASSERT_EQ(sf_sequence_data(mask.h, &m, &mst), SF_OK);
    double in_block = 0, in_frames = 0, total = 0;
    for (int64_t fr = 0; fr < 16; ++fr)
        for (int64_t y = 0; y < 24; ++y)
            for (int64_t x = 0; x < 32; ++x) {
                const float v = *reinterpret_cast<float*>(reinterpret_cast<char*>(m) + fr * mst.frame + y * mst.row + x * mst.pixel);
                total += v;
                in_frames += (fr >= 6 && fr <= 8) ? v : 0;
                in_block += (fr >= 6 && fr <= 8 && y >= 4 && y < 12 && x >= 8 && x < 20) ? v : 0;
            }
    EXPECT_GT(in_block, 0.9 * 3 * 8 * 12);
    EXPECT_GT(in_frames, 0.65 * total);

    const char* crops = nullptr;
    ASSERT_EQ(sf_filter_result_string(f, "crops", &crops), SF_OK);
    const std::string json = crops;
    size_t count = 0;
    int64_t width = 0, height = 0;
    ASSERT_EQ(sf_crops_windows(json.c_str(), nullptr, 0, &count, &width, &height), SF_OK);
    EXPECT_EQ(width, 32);
    EXPECT_EQ(height, 24);
    ASSERT_GE(count, 3u);  // at least one window in each of frames 6, 7, 8
    std::vector<sf_crop_window> windows(count);
    size_t written = 0;
    ASSERT_EQ(sf_crops_windows(json.c_str(), windows.data(), 2, &written, nullptr, nullptr), SF_OK);
    EXPECT_EQ(written, 2u);
    ASSERT_EQ(sf_crops_windows(json.c_str(), windows.data(), count, &written, nullptr, nullptr), SF_OK);
    EXPECT_EQ(written, count);
    int block_frames_with_windows = 0;
    for (const auto& w : windows) {
        block_frames_with_windows += w.frame >= 7 && w.frame <= 9 && w.index == 0;  // frame numbers 1..16
        EXPECT_LE(w.x + w.width, 32);
        EXPECT_LE(w.y + w.height, 24);
    }
    EXPECT_EQ(block_frames_with_windows, 3);
    EXPECT_EQ(sf_crops_windows("{\"format\": 1}", nullptr, 0, &count, nullptr, nullptr), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(sf_last_error()).find("crops JSON"), std::string::npos);
    EXPECT_EQ(sf_crops_windows(nullptr, nullptr, 0, &count, nullptr, nullptr), SF_ERROR_INVALID_ARGUMENT);

    // Merge the "re-render" (the noisy frames stand in for it) into the windows: the windows' pixels
    // change, the rest stays the denoised value.
    Owned merged;
    ASSERT_EQ(sf_sequence_create(sc.shape, &merged.h), SF_OK);
    sf_merge_options mo;
    sf_merge_options_init(&mo);
    EXPECT_EQ(mo.struct_size, sizeof mo);
    EXPECT_EQ(mo.feather, 0);
    mo.crops = json.c_str();
    int64_t replaced = 0;
    ASSERT_EQ(sf_merge(den.h, noisy.h, &mo, merged.h, &replaced), SF_OK) << sf_last_error();
    int64_t window_pixels = 0;
    for (const auto& w : windows) window_pixels += w.width * w.height;
    EXPECT_EQ(replaced, window_pixels);
    float* data = nullptr;
    sf_strides st;
    ASSERT_EQ(sf_sequence_data(merged.h, &data, &st), SF_OK);
    const auto& w0 = windows[0];
    const size_t inside = static_cast<size_t>((((w0.frame - 1) * 24 + w0.y) * 32 + w0.x) * 3);
    EXPECT_EQ(data[inside], sc.noisy[inside]);
    EXPECT_EQ(data[0], sc.denoised[0]);

    // Errors: no region, wrong struct size, mismatched re-render.
    sf_merge_options none;
    sf_merge_options_init(&none);
    EXPECT_EQ(sf_merge(den.h, noisy.h, &none, merged.h, nullptr), SF_ERROR_INVALID_ARGUMENT);
    mo.struct_size = 3;
    EXPECT_EQ(sf_merge(den.h, noisy.h, &mo, merged.h, nullptr), SF_ERROR_INVALID_ARGUMENT);
    mo.struct_size = sizeof mo;
    Owned small;
    ASSERT_EQ(sf_sequence_create(sf_shape{16, 24, 31, 3}, &small.h), SF_OK);
    EXPECT_EQ(sf_merge(den.h, small.h, &mo, merged.h, nullptr), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(sf_last_error()).find("31 x 24"), std::string::npos) << sf_last_error();
    mo.crops = "{\"format\": \"statfilter-crops\", \"version\": 1, \"width\": 32, \"height\": 24, \"frames\": "
               "[{\"frame\": 1, \"windows\": [{\"x\": 30, \"y\": 0, \"width\": 4, \"height\": 4}]}]}";
    EXPECT_EQ(sf_merge(den.h, noisy.h, &mo, merged.h, nullptr), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(sf_last_error()).find("extends past the image width 32"), std::string::npos);
    sf_filter_release(f);
}

TEST(DetectCapi, DegreeAboveFramesMinusOneFailsWithTheReason) {
    Scene sc;
    Owned den, noisy, out;
    ASSERT_EQ(sf_sequence_wrap(sc.denoised.data(), sc.shape, strides_of(sc.shape), &den.h), SF_OK);
    ASSERT_EQ(sf_sequence_wrap(sc.noisy.data(), sc.shape, strides_of(sc.shape), &noisy.h), SF_OK);
    ASSERT_EQ(sf_sequence_create(sc.shape, &out.h), SF_OK);
    sf_filter f = nullptr;
    ASSERT_EQ(sf_filter_create("detect", &f), SF_OK);
    ASSERT_EQ(sf_filter_set_int(f, "degree", 16), SF_OK);
    ASSERT_EQ(sf_filter_set_input(f, "noisy", noisy.h), SF_OK);
    EXPECT_EQ(sf_filter_execute(f, den.h, out.h), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(sf_filter_last_error(f)).find("degree 16 needs at least 17 frames; the sequence has 16"),
              std::string::npos)
        << sf_filter_last_error(f);
    sf_filter_release(f);
}

namespace {

TEST(DetectCapi, DegreePreviewColoursEachDegreeAndMarksTheUnexplained) {
    // One row: degrees 0, 4, 8 of a highest degree of 8, then 9 (no degree explains the pixel), NaN.
    const sf_shape shape{1, 1, 5, 1};
    std::vector<float> map = {0.0f, 4.0f, 8.0f, 9.0f, std::nanf("")};
    Owned wrapped, rgb;
    ASSERT_EQ(sf_sequence_wrap(map.data(), shape, strides_of(shape), &wrapped.h), SF_OK) << sf_last_error();
    ASSERT_EQ(sf_detect_degree_preview(wrapped.h, 8, &rgb.h), SF_OK) << sf_last_error();
    sf_shape out{};
    ASSERT_EQ(sf_sequence_shape(rgb.h, &out), SF_OK);
    EXPECT_EQ(out.frames, 1);
    EXPECT_EQ(out.height, 1);
    EXPECT_EQ(out.width, 5);
    ASSERT_EQ(out.channels, 3);
    float* data = nullptr;
    sf_strides st{};
    ASSERT_EQ(sf_sequence_data(rgb.h, &data, &st), SF_OK);
    auto at = [&](int64_t x, int c) { return *reinterpret_cast<const float*>(reinterpret_cast<const char*>(data) + x * st.pixel + c * st.channel); };
    // Degree 0: dark blue; the highest degree: yellow; half way between; unexplained: red.
    EXPECT_FLOAT_EQ(at(0, 0), 0.0f);
    EXPECT_FLOAT_EQ(at(0, 1), 0.15f);
    EXPECT_FLOAT_EQ(at(0, 2), 0.55f);
    EXPECT_FLOAT_EQ(at(1, 0), 0.4f);
    EXPECT_FLOAT_EQ(at(1, 1), 0.575f);
    EXPECT_FLOAT_EQ(at(1, 2), 0.3f);
    EXPECT_FLOAT_EQ(at(2, 0), 1.0f);
    EXPECT_FLOAT_EQ(at(2, 1), 1.0f);
    EXPECT_FLOAT_EQ(at(2, 2), 0.05f);
    for (int64_t x : {3, 4}) {  // above the highest degree, and a NaN: no degree explains it
        EXPECT_FLOAT_EQ(at(x, 0), 0.9f) << x;
        EXPECT_FLOAT_EQ(at(x, 1), 0.1f) << x;
        EXPECT_FLOAT_EQ(at(x, 2), 0.1f) << x;
    }
    const char* name = nullptr;
    ASSERT_EQ(sf_sequence_channel_name(rgb.h, 2, &name), SF_OK);
    EXPECT_STREQ(name, "B");
}

TEST(DetectCapi, DegreePreviewRefusesWhatIsNotADegreeMap) {
    const sf_shape shape{2, 2, 2, 1};
    std::vector<float> two_frames(8, 1.0f);
    Owned wrapped;
    ASSERT_EQ(sf_sequence_wrap(two_frames.data(), shape, strides_of(shape), &wrapped.h), SF_OK);
    sf_sequence out = reinterpret_cast<sf_sequence>(&wrapped);  // must be reset to NULL on failure
    EXPECT_EQ(sf_detect_degree_preview(wrapped.h, 8, &out), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(sf_last_error()).find("one frame of one channel"), std::string::npos) << sf_last_error();
    EXPECT_EQ(out, nullptr);
    EXPECT_EQ(sf_detect_degree_preview(nullptr, 8, &out), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(sf_detect_degree_preview(wrapped.h, 8, nullptr), SF_ERROR_INVALID_ARGUMENT);
}

}  // namespace
