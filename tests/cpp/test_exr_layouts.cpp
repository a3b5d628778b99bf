// EXR layouts beyond one full-frame part: data windows inside a display window (region renders,
// auto-cropped frames), parts of different windows, part 0's header attributes, deep files. Both
// the whole-sequence reader/writer and the streamed source/sink are checked on files written here.
#include <gtest/gtest.h>

#include <OpenImageIO/deepdata.h>

#include <filesystem>

#include "core_errors.hpp"
#include "exr_util.hpp"
#include "pipeline/frame_source.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_metadata.hpp"
#include "statfilter/sequence_io.hpp"
#include "test_util.hpp"

using namespace statfilter;
using namespace statfilter_test;

namespace {

const std::vector<std::string> kRGB = {"R", "G", "B"};

WriteOptions float_options() {
    WriteOptions o;
    o.half = false;
    return o;
}

ReadOptions channels(const std::string& list) {
    ReadOptions o;
    o.channels = list;
    return o;
}


// Copies a sequence through the streamed source and sink, reading each frame in two bands.
void stream_copy(const std::string& in, const std::string& out, const ReadOptions& read = ReadOptions()) {
    auto source = open_frame_source(in, read);
    const Shape& s = source->shape();
    OutputChecks checks;
    checks.width = s.width;
    checks.height = s.height;
    auto sink = open_frame_sink(out, float_options(), source->attributes(), checks);
    sink->set_attribute("statfilter:method", "copy");
    std::vector<float> frame(static_cast<size_t>(s.pixels() * s.channels));
    const int64_t half = s.height / 2;
    for (int64_t f = 0; f < s.frames; ++f) {
        source->read_rows(f, 0, half, frame.data());
        source->read_rows(f, half, s.height, frame.data() + half * s.width * s.channels);
        sink->write_frame(f, frame.data());
    }
    sink->commit();
}

void expect_windows(const OIIO::ImageSpec& spec, int x, int y, int w, int h, int full_w, int full_h) {
    EXPECT_EQ(spec.x, x);
    EXPECT_EQ(spec.y, y);
    EXPECT_EQ(spec.width, w);
    EXPECT_EQ(spec.height, h);
    EXPECT_EQ(spec.full_x, 0);
    EXPECT_EQ(spec.full_y, 0);
    EXPECT_EQ(spec.full_width, full_w);
    EXPECT_EQ(spec.full_height, full_h);
}

}  // namespace

// A region render: the data window 150 x 120 at (5, 0) of a 160 x 120 display window.
class Region : public ::testing::Test {
protected:
    static constexpr int kW = 150, kH = 120, kX = 5, kFullW = 160, kFullH = 120;
    void SetUp() override {
        for (int64_t f = 1; f <= 2; ++f) {
            ExrPart part{"", kRGB, make_pixels(kW, kH, 3, f)};
            part.x = kX, part.data_width = kW, part.data_height = kH;
            write_exr(dir.file("region.000" + std::to_string(f) + ".exr"), kFullW, kFullH, {part});
        }
        std::filesystem::create_directory(dir.path() / "out");
    }
    void expect_region(const std::string& path, int64_t f) {
        const ExrImage out = read_exr(path);
        expect_windows(out.spec, kX, 0, kW, kH, kFullW, kFullH);
        EXPECT_EQ(out.pixels, make_pixels(kW, kH, 3, f));
    }
    TempDir dir;
};

TEST_F(Region, ReadAsItsDataWindowAndWrittenBackInPlace) {
    auto seq = read_sequence(dir.file("region.####.exr"), ReadOptions());
    ASSERT_EQ(seq->shape(), (Shape{2, kH, kW, 3}));
    EXPECT_EQ(seq->at(1, 7, 9, 2), sample_value(2, 7, 9, 2));
    write_sequence(*seq, dir.file("out/copy.####.exr"), float_options());
    expect_region(dir.file("out/copy.0001.exr"), 1);
    expect_region(dir.file("out/copy.0002.exr"), 2);
}

TEST_F(Region, StreamedCopyKeepsTheWindows) {
    stream_copy(dir.file("region.####.exr"), dir.file("out/stream.####.exr"));
    expect_region(dir.file("out/stream.0001.exr"), 1);
    expect_region(dir.file("out/stream.0002.exr"), 2);
    EXPECT_EQ(read_exr(dir.file("out/stream.0002.exr")).spec.get_string_attribute("statfilter:method"), "copy");
}

TEST_F(Region, AFrameOfAnotherSizeGoesAtTheOrigin) {
    auto seq = read_sequence(dir.file("region.####.exr"), ReadOptions());
    Sequence smaller(Shape{2, 4, 4, 3});
    smaller.copy_attributes_from(*seq);
    write_sequence(smaller, dir.file("out/small.####.exr"), float_options());
    expect_windows(read_exr(dir.file("out/small.0001.exr")).spec, 0, 0, 4, 4, 4, 4);
}

// Auto-cropped frames: each frame's data window is its own, inside one 12 x 10 display window.
class Cropped : public ::testing::Test {
protected:
    static constexpr int kFullW = 12, kFullH = 10;
    struct Box {
        int x, y, w, h;
    };
    const Box boxes[3] = {{0, 0, 12, 10}, {2, 3, 9, 6}, {5, 1, 4, 4}};
    void SetUp() override {
        for (int f = 0; f < 3; ++f) {
            ExrPart part{"", kRGB, make_pixels(boxes[f].w, boxes[f].h, 3, f + 1)};
            part.x = boxes[f].x, part.y = boxes[f].y, part.data_width = boxes[f].w, part.data_height = boxes[f].h;
            write_exr(dir.file("crop.000" + std::to_string(f + 1) + ".exr"), kFullW, kFullH, {part});
        }
        std::filesystem::create_directory(dir.path() / "out");
    }
    // The value at display pixel (x, y) of frame index f: the file's, or 0 outside its data window.
    float expected(int f, int y, int x, int c) const {
        const Box& b = boxes[f];
        if (x < b.x || y < b.y || x >= b.x + b.w || y >= b.y + b.h) return 0.0f;
        return sample_value(f + 1, y - b.y, x - b.x, c);
    }
    TempDir dir;
};

TEST_F(Cropped, ReadOnTheDisplayWindowWithZeroOutside) {
    auto seq = read_sequence(dir.file("crop.####.exr"), ReadOptions());
    ASSERT_EQ(seq->shape(), (Shape{3, kFullH, kFullW, 3}));
    for (int f = 0; f < 3; ++f)
        for (int y = 0; y < kFullH; ++y)
            for (int x = 0; x < kFullW; ++x)
                for (int c = 0; c < 3; ++c) ASSERT_EQ(seq->at(f, y, x, c), expected(f, y, x, c)) << f << " " << y << " " << x;
    EXPECT_TRUE(seq->metadata()[0].file_data.empty());  // frame 1 covers the display window
    EXPECT_EQ(seq->metadata()[1].file_data, (PixelWindow{2, 3, 9, 6}));
    write_sequence(*seq, dir.file("out/full.####.exr"), float_options());
    expect_windows(read_exr(dir.file("out/full.0002.exr")).spec, 0, 0, kFullW, kFullH, kFullW, kFullH);
}

TEST_F(Cropped, StreamedReadsTheSamePixels) {
    auto whole = read_sequence(dir.file("crop.####.exr"), ReadOptions());
    stream_copy(dir.file("crop.####.exr"), dir.file("out/stream.####.exr"));
    for (int f = 0; f < 3; ++f) {
        const ExrImage out = read_exr(dir.file("out/stream.000" + std::to_string(f + 1) + ".exr"));
        expect_windows(out.spec, 0, 0, kFullW, kFullH, kFullW, kFullH);
        std::vector<float> frame(out.pixels.size());
        whole->get_frame(f, frame.data());
        EXPECT_EQ(out.pixels, frame) << "frame " << f + 1;
    }
}

// A multi-part file whose second part is a region of the first's display window.
class PartWindows : public ::testing::Test {
protected:
    static constexpr int kW = 8, kH = 6;
    void SetUp() override {
        for (int64_t f = 1; f <= 2; ++f) {
            ExrPart beauty{"ViewLayer.Combined",
                           {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B"},
                           make_pixels(kW, kH, 3, f)};
            beauty.attributes = {{"cycles.ViewLayer.total_time", "00:12.50"}, {"camera", "Camera.001"}};
            ExrPart light{"ViewLayer.Emit", {"ViewLayer.Emit.R", "ViewLayer.Emit.G", "ViewLayer.Emit.B"},
                          make_pixels(3, 2, 3, f, 100.0f)};
            light.x = 4, light.y = 1, light.data_width = 3, light.data_height = 2;
            light.attributes = {{"camera", "not part 0's"}};
            write_exr(dir.file("parts.000" + std::to_string(f) + ".exr"), kW, kH, {beauty, light});
        }
        std::filesystem::create_directory(dir.path() / "out");
    }
    TempDir dir;
};

TEST_F(PartWindows, APartChosenByNameUsesItsOwnWindow) {
    auto seq = read_sequence(dir.file("parts.####.exr"), channels("ViewLayer.Emit"));
    ASSERT_EQ(seq->shape(), (Shape{2, 2, 3, 3}));
    EXPECT_EQ(seq->at(1, 1, 2, 0), sample_value(2, 1, 2, 0) + 100.0f);
    stream_copy(dir.file("parts.####.exr"), dir.file("out/emit.####.exr"), channels("ViewLayer.Emit"));
    expect_windows(read_exr(dir.file("out/emit.0001.exr")).spec, 4, 1, 3, 2, kW, kH);
}

TEST_F(PartWindows, ChannelsOfBothPartsAreReadOnTheDisplayWindow) {
    auto seq = read_sequence(dir.file("parts.####.exr"), channels("ViewLayer.Combined.R,ViewLayer.Emit.R"));
    ASSERT_EQ(seq->shape(), (Shape{2, kH, kW, 2}));
    EXPECT_EQ(seq->at(0, 5, 7, 0), sample_value(1, 5, 7, 0));
    EXPECT_EQ(seq->at(0, 2, 6, 1), sample_value(1, 1, 2, 0) + 100.0f);
    EXPECT_EQ(seq->at(0, 0, 0, 1), 0.0f);  // outside the Emit part's data window
}

TEST_F(PartWindows, PartZerosAttributesAreCarriedToTheOutput) {
    stream_copy(dir.file("parts.####.exr"), dir.file("out/emit.####.exr"), channels("ViewLayer.Emit"));
    const ExrImage out = read_exr(dir.file("out/emit.0002.exr"));
    EXPECT_EQ(out.spec.get_string_attribute("cycles.ViewLayer.total_time"), "00:12.50");
    EXPECT_EQ(out.spec.get_string_attribute("camera"), "Camera.001");  // part 0's wins
    EXPECT_EQ(out.spec.get_string_attribute("statfilter:method"), "copy");
    auto seq = read_sequence(dir.file("parts.####.exr"), channels("ViewLayer.Emit"));
    write_sequence(*seq, dir.file("out/whole.####.exr"), float_options());
    EXPECT_EQ(read_exr(dir.file("out/whole.0001.exr")).spec.get_string_attribute("cycles.ViewLayer.total_time"),
              "00:12.50");
}

TEST(DeepExr, IsRefusedNamingTheFile) {
    TempDir dir;
    const std::string path = dir.file("deep.0001.exr");
    OIIO::ImageSpec spec(4, 3, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.deep = true;
    OIIO::DeepData deep;
    deep.init(spec);
    for (int64_t p = 0; p < 12; ++p) {
        deep.set_samples(p, 1);
        for (int c = 0; c < 4; ++c) deep.set_deep_value(p, c, 0, 0.5f);
    }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    if (!out->supports("deepdata")) GTEST_SKIP() << "this OpenImageIO writes no deep EXR";
    ASSERT_TRUE(out->open(path, spec) && out->write_deep_image(deep) && out->close()) << out->geterror();
    for (bool streamed : {false, true}) {
        const auto [status, message] = error_of([&] {
            if (streamed)
                open_frame_source(dir.file("deep.####.exr"), ReadOptions());
            else
                read_sequence(dir.file("deep.####.exr"), ReadOptions());
        });
        EXPECT_EQ(status, Status::Unsupported);
        EXPECT_NE(message.find("deep.0001.exr"), std::string::npos) << message;
        EXPECT_NE(message.find("deep"), std::string::npos) << message;
    }
}

TEST_F(Region, TiledOnRequestAndReadBackStreamed) {
    auto seq = read_sequence(dir.file("region.####.exr"), ReadOptions());
    WriteOptions tiled = float_options();
    tiled.tile_size = 32;
    write_sequence(*seq, dir.file("out/tiled.####.exr"), tiled);
    const ExrImage out = read_exr(dir.file("out/tiled.0001.exr"));
    EXPECT_EQ(out.spec.tile_width, 32);
    EXPECT_EQ(out.spec.tile_height, 32);
    expect_region(dir.file("out/tiled.0001.exr"), 1);
    // A tiled input streams like a scanline one.
    stream_copy(dir.file("out/tiled.####.exr"), dir.file("out/again.####.exr"));
    expect_region(dir.file("out/again.0002.exr"), 2);
    EXPECT_EQ(read_exr(dir.file("out/again.0002.exr")).spec.tile_width, 0);
    tiled.tile_size = -1;
    EXPECT_EQ(error_of([&] { write_sequence(*seq, dir.file("out/bad.####.exr"), tiled); }).first,
              Status::InvalidArgument);
}

// Frames taller than the reader's 256-row blocks, each compression, half channels, float ones and a
// mix of both in one part (read through the library's own conversion): every band gives the
// library's float values of the file, bit for bit.
TEST(TallFrames, BandsAcrossTheReadBlocksGiveTheLibrarysValues) {
    TempDir dir;
    constexpr int kW = 5, kH = 700;
    const std::vector<std::pair<int64_t, int64_t>> bands = {{0, kH}, {13, 611}, {255, 257}, {256, 512}, {699, 700}};
    int files = 0;
    for (const char* compression : {"zip", "zips", "piz", "dwab", "none"})
        for (int formats = 0; formats < 3; ++formats) {  // all half, all float, half and float
            const std::string path = dir.file("tall" + std::to_string(files++) + ".exr");
            OIIO::ImageSpec spec(kW, kH, 3, formats == 1 ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF);
            if (formats == 2) spec.channelformats = {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::HALF};
            spec.channelnames = kRGB;
            spec.attribute("compression", compression);
            std::vector<float> pixels = make_pixels(kW, kH, 3, 1);
            for (size_t i = 0; i < pixels.size(); i += 7) pixels[i] = 1.0f / 3.0f + static_cast<float>(i);  // not half-exact
            auto out = OIIO::ImageOutput::create(path);
            ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
            const ExrImage expected = read_exr(path);
            auto source = open_frame_source(path, ReadOptions());
            ASSERT_EQ(source->shape().height, kH);
            for (const auto& [y0, y1] : bands) {
                std::vector<float> got(static_cast<size_t>((y1 - y0) * kW * 3), -99.0f);
                source->read_rows(0, y0, y1, got.data());
                for (size_t i = 0; i < got.size(); ++i)
                    ASSERT_EQ(float_bits(got[i]), float_bits(expected.pixels[static_cast<size_t>(y0 * kW * 3) + i]))
                        << compression << " formats " << formats << " rows " << y0 << "-" << y1 << " value " << i;
            }
        }
}
