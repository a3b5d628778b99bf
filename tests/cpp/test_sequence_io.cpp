// Reading and writing frame sequences: exact round trips, metadata, compression, Blender-style
// multi-part files and (when present) the real renders in $STATFILTER_SHARED_DATA.
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "core_errors.hpp"
#include "exr_util.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/frame_metadata.hpp"
#include "statfilter/sequence_io.hpp"
#include "test_util.hpp"

using namespace statfilter;
using namespace statfilter_test;

namespace {

// A 3-frame sequence of 5 x 4 pixels, named RGB channels, frames 101..103, sample_value() data.
std::unique_ptr<Sequence> make_sequence() {
    auto seq = std::make_unique<Sequence>(Shape{3, 4, 5, 3});
    seq->channel_names() = {"diffuse.R", "diffuse.G", "diffuse.B"};
    seq->frame_numbers() = {101, 102, 103};
    const Shape& s = seq->shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) seq->at(f, y, x, c) = sample_value(f, y, x, c);
    return seq;
}

WriteOptions float_options() {
    WriteOptions o;
    o.half = false;
    return o;
}

// Every sample of b equals (bit for bit) expected(a's sample).
template <class Expected>
void expect_samples(const Sequence& a, const Sequence& b, Expected&& expected) {
    ASSERT_EQ(a.shape(), b.shape());
    const Shape& s = a.shape();
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c)
                    ASSERT_EQ(float_bits(b.at(f, y, x, c)), float_bits(expected(a.at(f, y, x, c))))
                        << "frame " << f << " y " << y << " x " << x << " c " << c << ": " << a.at(f, y, x, c)
                        << " -> " << b.at(f, y, x, c);
}


ReadOptions channels(const std::string& list) {
    ReadOptions o;
    o.channels = list;
    return o;
}

}  // namespace

TEST(SequenceIO, FloatRoundTripIsBitExact) {
    TempDir dir;
    auto seq = make_sequence();
    const float extremes[] = {-1.5f, 1e-30f, -1e-30f, 1e30f, -1e30f, 0.0f, -0.0f,
                              std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max(),
                              std::numeric_limits<float>::lowest(), 3.14159274f};
    for (int i = 0; i < 11; ++i) seq->at(1, i / 5, i % 5, i % 3) = extremes[i];

    write_sequence(*seq, dir.file("out.####.exr"), float_options());
    EXPECT_EQ(files_in(dir.path()), (std::vector<std::string>{"out.0101.exr", "out.0102.exr", "out.0103.exr"}));
    EXPECT_EQ(read_exr(dir.file("out.0101.exr")).spec.format, OIIO::TypeDesc::FLOAT);

    auto back = read_sequence(dir.file("out.####.exr"), ReadOptions());
    expect_samples(*seq, *back, [](float v) { return v; });
    EXPECT_EQ(back->channel_names(), seq->channel_names());
    EXPECT_EQ(back->frame_numbers(), seq->frame_numbers());
}

TEST(SequenceIO, HalfRoundTripRoundsToHalfPrecision) {
    TempDir dir;
    auto seq = make_sequence();
    seq->at(0, 0, 0, 0) = 65504.0f;   // half's largest finite value
    seq->at(0, 0, 1, 0) = -0.1f;      // not representable: rounds
    seq->at(0, 0, 2, 0) = 1e-6f;      // a half subnormal
    seq->at(0, 0, 3, 0) = 1.0f / 3.0f;
    write_sequence(*seq, dir.file("h.%04d.exr"), WriteOptions());  // half is the default
    EXPECT_EQ(read_exr(dir.file("h.0101.exr")).spec.format, OIIO::TypeDesc::HALF);

    auto back = read_sequence(dir.file("h.%04d.exr"), ReadOptions());
    expect_samples(*seq, *back, [](float v) { return static_cast<float>(Imath::half(v)); });
    // And within half's relative precision of the original.
    EXPECT_NEAR(back->at(0, 0, 3, 0), 1.0f / 3.0f, 1.0f / 3.0f / 1024);
    EXPECT_EQ(back->frame_numbers(), seq->frame_numbers());
}

// The writer rounds to half itself; its files hold the halves the library's own conversion gives, bit
// for bit: ties to even, subnormals, signed zeros, infinities, NaN, and with clamping the range's ends.
TEST(SequenceIO, HalfFilesHoldTheLibrarysHalves) {
    TempDir dir;
    constexpr float inf = std::numeric_limits<float>::infinity();
    const float values[] = {1.0f + 1.0f / 2048,  1.0f + 3.0f / 2048, -1.0f - 1.0f / 2048, 1e-6f, -1e-7f, 6e-8f, 2e-8f,
                            0.0f,  -0.0f, inf, -inf, std::numeric_limits<float>::quiet_NaN(), 65504.0f, 65519.0f,
                            -65519.0f, 1.0f / 3.0f, 1e30f, -1e30f, 123.456f, std::numeric_limits<float>::denorm_min()};
    const int n = static_cast<int>(sizeof values / sizeof values[0]);
    for (bool clamp : {false, true}) {
        Sequence seq(Shape{1, 1, n, 1});
        seq.channel_names() = {"Y"};
        seq.frame_numbers() = {1};
        std::vector<float> library(values, values + n);  // what the library is handed to convert
        for (int i = 0; i < n; ++i) {
            const bool beyond = std::isfinite(values[i]) && std::fabs(values[i]) > 65504.0f;
            seq.at(0, 0, i, 0) = clamp || !beyond ? values[i] : 0.0f;  // unclamped, beyond is refused
            library[i] = beyond ? (clamp ? std::copysign(65504.0f, values[i]) : 0.0f) : values[i];
        }
        WriteOptions o;
        o.clamp_half = clamp;
        const std::string ours = dir.file(std::string("ours") + (clamp ? "c" : "") + ".%04d.exr");
        write_sequence(seq, ours, o);
        const std::string theirs = dir.file(std::string("theirs") + (clamp ? "c" : "") + ".exr");
        OIIO::ImageSpec spec(n, 1, 1, OIIO::TypeDesc::HALF);
        spec.channelnames = {"Y"};
        auto out = OIIO::ImageOutput::create(theirs);
        ASSERT_TRUE(out && out->open(theirs, spec) && out->write_image(OIIO::TypeDesc::FLOAT, library.data()) && out->close());
        const auto halves = [](const std::string& path) {
            auto in = OIIO::ImageInput::open(path);
            std::vector<uint16_t> bits(static_cast<size_t>(in->spec().width));
            EXPECT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::HALF, bits.data()));
            return bits;
        };
        const std::vector<uint16_t> a = halves(FramePattern(ours).format(1)), b = halves(theirs);
        for (int i = 0; i < n; ++i) EXPECT_EQ(a[i], b[i]) << "value " << values[i] << (clamp ? " clamped" : "");
    }
}

TEST(SequenceIO, MetadataTravelsThroughReadAndWrite) {
    TempDir dir;
    auto seq = make_sequence();
    for (int64_t f = 0; f < 3; ++f) {
        seq->metadata()[f].attribute("studio:shot", "sh010");
        seq->metadata()[f].attribute("studio:take", static_cast<int>(f + 7));
    }
    write_sequence(*seq, dir.file("a.####.exr"), float_options());
    // The attribute is in the file itself, as OIIO sees it.
    EXPECT_EQ(read_exr(dir.file("a.0102.exr")).spec.get_string_attribute("studio:shot"), "sh010");

    auto back = read_sequence(dir.file("a.####.exr"), ReadOptions());
    // ... and a second generation keeps it too (read metadata is written back).
    std::filesystem::create_directory(dir.path() / "gen2");
    write_sequence(*back, dir.file("gen2/b.####.exr"), float_options());
    auto gen2 = read_sequence(dir.file("gen2/b.####.exr"), ReadOptions());
    for (const Sequence* s : {back.get(), gen2.get()})
        for (int64_t f = 0; f < 3; ++f) {
            EXPECT_EQ(s->metadata()[f].get_string("studio:shot"), "sh010") << "frame " << f;
            EXPECT_EQ(s->metadata()[f].get_int("studio:take"), f + 7) << "frame " << f;
        }
}

TEST(SequenceIO, CompressionIsHonoured) {
    for (const char* compression : {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "dwaa"}) {
        TempDir dir;
        auto seq = make_sequence();
        WriteOptions o;
        o.compression = compression;
        write_sequence(*seq, dir.file("c.####.exr"), o);
        EXPECT_EQ(read_exr(dir.file("c.0103.exr")).spec.get_string_attribute("compression"), compression);
    }
}

TEST(SequenceIO, UnknownCompressionIsRejectedBeforeWriting) {
    TempDir dir;
    auto seq = make_sequence();
    WriteOptions o;
    o.compression = "lzma";
    const auto [status, message] = error_of([&] { write_sequence(*seq, dir.file("c.####.exr"), o); });
    EXPECT_EQ(status, Status::InvalidArgument);
    EXPECT_NE(message.find("lzma"), std::string::npos) << message;
    EXPECT_TRUE(files_in(dir.path()).empty());
}

TEST(SequenceIO, FrameSubsetAndProgress) {
    TempDir dir;
    auto seq = make_sequence();
    std::vector<double> fractions;
    WriteOptions wo = float_options();
    wo.progress = Progress([&](double f, const char*) { return fractions.push_back(f), true; });
    write_sequence(*seq, dir.file("p.####.exr"), wo);
    ASSERT_FALSE(fractions.empty());
    for (double f : fractions) EXPECT_TRUE(f >= 0 && f <= 1) << f;
    EXPECT_EQ(fractions.back(), 1.0);

    ReadOptions ro;
    ro.frames = "101,103";
    auto back = read_sequence(dir.file("p.####.exr"), ro);
    EXPECT_EQ(back->frame_numbers(), (std::vector<int64_t>{101, 103}));
    EXPECT_EQ(back->at(1, 2, 3, 1), seq->at(2, 2, 3, 1));
}

TEST(SequenceIO, SingleFramePatternWithoutToken) {
    TempDir dir;
    Sequence seq(Shape{1, 2, 2, 1});
    seq.at(0, 1, 1, 0) = 4.5f;
    write_sequence(seq, dir.file("still.exr"), float_options());
    auto back = read_sequence(dir.file("still.exr"), ReadOptions());
    EXPECT_EQ(back->shape(), seq.shape());
    EXPECT_EQ(back->at(0, 1, 1, 0), 4.5f);
}

TEST(SequenceIO, ChannelListNamingNothingIsRefused) {
    TempDir dir;
    write_sequence(*make_sequence(), dir.file("c.####.exr"), float_options());
    for (const char* list : {",", " ", ",,,", " , ,"}) {
        ReadOptions o;
        o.channels = list;
        const auto [status, message] = error_of([&] { read_sequence(dir.file("c.####.exr"), o); });
        EXPECT_EQ(status, Status::InvalidArgument) << list;
        EXPECT_NE(message.find("names no channel"), std::string::npos) << message;
    }
}

// Frames asked for by number are all checked before any memory is taken, and reported together.
TEST(SequenceIO, MissingExplicitFramesAreReportedBeforeReading) {
    TempDir dir;
    write_sequence(*make_sequence(), dir.file("c.####.exr"), float_options());
    ReadOptions o;
    o.frames = "101-20000";
    const auto [status, message] = error_of([&] { read_sequence(dir.file("c.####.exr"), o); });
    EXPECT_EQ(status, Status::NotFound);
    EXPECT_NE(message.find("frames 104-20000 are missing (found 101-103; the first missing is '" +
                           dir.file("c.0104.exr") + "')"),
              std::string::npos)
        << message;
}

// Only regular files are frames: a FIFO would block the reader forever, a device never end.
TEST(SequenceIO, FifoAndDevicesAreNotFrames) {
    TempDir dir;
    write_sequence(*make_sequence(), dir.file("c.####.exr"), float_options());
    ASSERT_EQ(::mkfifo(dir.file("c.0104.exr").c_str(), 0600), 0);
    fs::create_symlink("/dev/zero", dir.file("c.0105.exr"));
    const std::vector<std::pair<std::string, std::string>> cases = {{"101-104", "a FIFO"}, {"105", "a character device"}};
    for (const auto& [frames, kind] : cases) {
        ReadOptions o;
        o.frames = frames;
        const auto [status, message] = error_of([&] { read_sequence(dir.file("c.####.exr"), o); });
        EXPECT_EQ(status, Status::Io) << frames;
        EXPECT_NE(message.find(kind), std::string::npos) << message;
        EXPECT_NE(message.find("not a regular file"), std::string::npos) << message;
    }
}

// A Blender-like multi-part sequence: the beauty in part 0, the indirect light in part 1.
class MultiPart : public ::testing::Test {
protected:
    static constexpr int kW = 6, kH = 4;
    void SetUp() override {
        for (int64_t f = 1; f <= 3; ++f)
            write_exr(dir.file("frame." + std::to_string(10000 + f).substr(1) + ".exr"), kW, kH,
                      {ExrPart{"ViewLayer.Combined",
                               {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B",
                                "ViewLayer.Combined.A"},
                               make_pixels(kW, kH, 4, f)},
                       ExrPart{"ViewLayer.Diffuse Indirect",
                               {"ViewLayer.Diffuse Indirect.R", "ViewLayer.Diffuse Indirect.G",
                                "ViewLayer.Diffuse Indirect.B"},
                               make_pixels(kW, kH, 3, f, 1000.0f)}});
    }
    std::string pattern() const { return dir.file("frame.####.exr"); }
    TempDir dir;
};

TEST_F(MultiPart, LayerFromTheSecondPart) {
    auto seq = read_sequence(pattern(), channels("ViewLayer.Diffuse Indirect"));
    ASSERT_EQ(seq->shape(), (Shape{3, kH, kW, 3}));
    EXPECT_EQ(seq->channel_names(), (std::vector<std::string>{"R", "G", "B"}));
    EXPECT_EQ(seq->frame_numbers(), (std::vector<int64_t>{1, 2, 3}));
    for (int64_t f = 0; f < 3; ++f)
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(seq->at(f, y, x, c), sample_value(f + 1, y, x, c) + 1000.0f);
}

TEST_F(MultiPart, SingleChannelsFromBothParts) {
    auto seq = read_sequence(pattern(), channels("ViewLayer.Combined.R, ViewLayer.Diffuse Indirect.G"));
    ASSERT_EQ(seq->shape(), (Shape{3, kH, kW, 2}));
    EXPECT_EQ(seq->channel_names(),
              (std::vector<std::string>{"ViewLayer.Combined.R", "ViewLayer.Diffuse Indirect.G"}));
    EXPECT_EQ(seq->at(2, 3, 5, 0), sample_value(3, 3, 5, 0));
    EXPECT_EQ(seq->at(2, 3, 5, 1), sample_value(3, 3, 5, 1) + 1000.0f);
}

TEST_F(MultiPart, StarReadsEveryChannelOfEveryPart) {
    auto seq = read_sequence(pattern(), channels("*"));
    EXPECT_EQ(seq->channel_names(),
              (std::vector<std::string>{"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B",
                                        "ViewLayer.Combined.A", "ViewLayer.Diffuse Indirect.R",
                                        "ViewLayer.Diffuse Indirect.G", "ViewLayer.Diffuse Indirect.B"}));
    EXPECT_EQ(seq->at(1, 2, 3, 3), sample_value(2, 2, 3, 3));
    EXPECT_EQ(seq->at(1, 2, 3, 6), sample_value(2, 2, 3, 2) + 1000.0f);
}

TEST_F(MultiPart, EmptySelectionReadsTheLightPassesWithoutAlpha) {
    auto seq = read_sequence(pattern(), channels(""));
    EXPECT_EQ(seq->channel_names(),
              (std::vector<std::string>{"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B",
                                        "ViewLayer.Diffuse Indirect.R", "ViewLayer.Diffuse Indirect.G",
                                        "ViewLayer.Diffuse Indirect.B"}));
    EXPECT_EQ(seq->at(1, 2, 3, 2), sample_value(2, 2, 3, 2));
    EXPECT_EQ(seq->at(1, 2, 3, 5), sample_value(2, 2, 3, 2) + 1000.0f);
}

TEST_F(MultiPart, SeveralLayersKeepTheirNamesThroughWrite) {
    auto seq = read_sequence(pattern(), channels("ViewLayer.Diffuse Indirect, ViewLayer.Combined"));
    const std::vector<std::string> names = {"ViewLayer.Diffuse Indirect.R", "ViewLayer.Diffuse Indirect.G",
                                            "ViewLayer.Diffuse Indirect.B", "ViewLayer.Combined.R",
                                            "ViewLayer.Combined.G", "ViewLayer.Combined.B", "ViewLayer.Combined.A"};
    EXPECT_EQ(seq->channel_names(), names);
    std::filesystem::create_directory(dir.path() / "out");
    write_sequence(*seq, dir.file("out/both.####.exr"), float_options());
    // EXR keeps channels sorted by name: the names, not their order, are what must survive.
    std::vector<std::string> written = read_exr(dir.file("out/both.0001.exr")).spec.channelnames, expected = names;
    std::sort(written.begin(), written.end());
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(written, expected);
    EXPECT_EQ(read_sequence(dir.file("out/both.####.exr"), channels("ViewLayer.Diffuse Indirect"))->at(0, 1, 2, 1),
              sample_value(1, 1, 2, 1) + 1000.0f);
}

TEST_F(MultiPart, AChannelTakenTwiceIsRefused) {
    const auto [status, message] =
        error_of([&] { read_sequence(pattern(), channels("ViewLayer.Combined,ViewLayer.Combined.R")); });
    EXPECT_EQ(status, Status::InvalidArgument);
    EXPECT_NE(message.find("'ViewLayer.Combined.R'"), std::string::npos) << message;
    EXPECT_NE(message.find("twice"), std::string::npos) << message;
}

TEST(DefaultChannels, DataPassesAreLeftOut) {
    for (const char* light : {"ViewLayer.Combined.R", "ViewLayer.Diffuse Direct.G", "ViewLayer.Glossy Indirect.B",
                              "ViewLayer.Emit.R", "ViewLayer.Environment.R", "ViewLayer.Noisy Image.R", "R", "Y"})
        EXPECT_TRUE(is_light_channel(light)) << light;
    for (const char* data : {"ViewLayer.Normal.X", "ViewLayer.Denoising Albedo.R", "ViewLayer.Diffuse Color.R",
                             "ViewLayer.Glossy Color.G", "ViewLayer.Depth.Z", "Z", "ViewLayer.Vector.X",
                             "ViewLayer.Combined.A", "A", "ViewLayer.Alpha.A", "ViewLayer.Denoising Normal.X",
                             "ViewLayer.Mist.Z", "ViewLayer.IndexOB.X", "ViewLayer.CryptoObject00.R", "albedo.R"})
        EXPECT_FALSE(is_light_channel(data)) << data;
}

TEST(DefaultChannels, AFileWithoutLayersIsReadWhole) {
    TempDir dir;
    write_exr(dir.file("rgba.0001.exr"), 3, 2, {"R", "G", "B", "A"}, make_pixels(3, 2, 4, 1));
    auto seq = read_sequence(dir.file("rgba.####.exr"), ReadOptions());
    EXPECT_EQ(seq->channel_names(), (std::vector<std::string>{"R", "G", "B", "A"}));
    EXPECT_EQ(select_file_channels(dir.file("rgba.0001.exr"), ""), (std::vector<std::string>{"R", "G", "B", "A"}));
}

TEST(DefaultChannels, AFileOfDataPassesOnlyNamesWhatToDo) {
    TempDir dir;
    write_exr(dir.file("aux.0001.exr"), 3, 2, {"ViewLayer.Normal.X", "ViewLayer.Depth.Z"}, make_pixels(3, 2, 2, 1));
    const auto [status, message] = error_of([&] { read_sequence(dir.file("aux.####.exr"), ReadOptions()); });
    EXPECT_EQ(status, Status::NotFound);
    EXPECT_NE(message.find("aux.0001.exr"), std::string::npos) << message;
    EXPECT_NE(message.find("ViewLayer.Normal.X"), std::string::npos) << message;
    EXPECT_EQ(read_sequence(dir.file("aux.####.exr"), channels("*"))->shape().channels, 2);
}

TEST_F(MultiPart, MissingLayerListsTheAvailableChannels) {
    const auto [status, message] = error_of([&] { read_sequence(pattern(), channels("ViewLayer.Normal")); });
    EXPECT_EQ(status, Status::NotFound);
    EXPECT_NE(message.find("ViewLayer.Normal"), std::string::npos) << message;
    EXPECT_NE(message.find("frame.0001.exr"), std::string::npos) << message;
    EXPECT_NE(message.find("ViewLayer.Diffuse Indirect.B"), std::string::npos) << message;
}

TEST_F(MultiPart, LayerRoundTripsThroughWrite) {
    auto seq = read_sequence(pattern(), channels("ViewLayer.Diffuse Indirect"));
    std::filesystem::create_directory(dir.path() / "out");
    write_sequence(*seq, dir.file("out/indirect.####.exr"), float_options());
    const ExrImage written = read_exr(dir.file("out/indirect.0002.exr"));
    EXPECT_EQ(written.spec.nchannels, 3);
    EXPECT_EQ(written.spec.channel_name(0), "R");
    EXPECT_EQ(written.pixels, make_pixels(kW, kH, 3, 2, 1000.0f));
}

// The real renders: only when the shared data directory is there.
class SharedData : public ::testing::Test {
protected:
    void SetUp() override {
        root = shared_data_dir();
        if (root.empty()) GTEST_SKIP() << "STATFILTER_SHARED_DATA is not set or not a directory";
    }
    std::filesystem::path root;
};

TEST_F(SharedData, NoisyIndirectSequence) {
    const std::string pattern = (root / "cornell_moving/spp0016/indirect.####.exr").string();
    if (FramePattern(pattern).scan().empty()) GTEST_SKIP() << "no " << pattern;
    auto seq = read_sequence(pattern, ReadOptions());
    ASSERT_EQ(seq->shape(), (Shape{32, 120, 160, 3}));
    EXPECT_EQ(seq->channel_names(), (std::vector<std::string>{"R", "G", "B"}));
    EXPECT_EQ(seq->frame_numbers().front(), 1);
    EXPECT_EQ(seq->frame_numbers().back(), 32);
    // Frame 17 as OIIO reads it directly.
    const ExrImage direct = read_exr(FramePattern(pattern).format(17));
    std::vector<float> frame(direct.pixels.size());
    seq->get_frame(16, frame.data());
    EXPECT_EQ(frame, direct.pixels);
    // Real indirect light: finite, non-negative, not all zero.
    for (int64_t c = 0; c < 3; ++c) {
        const ChannelStats st = channel_stats(*seq, c);
        EXPECT_EQ(st.nan_count + st.inf_count, 0);
        EXPECT_GE(st.min, 0.0);
        EXPECT_GT(st.mean, 0.0);
    }
}

TEST_F(SharedData, BlenderMultiPartLayer) {
    const std::string pattern = (root / "raw/cornell_moving_spp0016/frame.####.exr").string();
    const std::vector<int64_t> frames = FramePattern(pattern).scan();
    if (frames.empty()) GTEST_SKIP() << "no " << pattern;
    auto seq = read_sequence(pattern, channels("ViewLayer.Diffuse Indirect"));
    ASSERT_EQ(seq->shape(), (Shape{static_cast<int64_t>(frames.size()), 120, 160, 3}));
    EXPECT_EQ(seq->channel_names(), (std::vector<std::string>{"R", "G", "B"}));
    EXPECT_EQ(seq->frame_numbers(), frames);
    // The values are those of the file's "ViewLayer.Diffuse Indirect" part.
    const std::string first = FramePattern(pattern).format(frames.front());
    int part = -1;
    for (int s = 0; s < 16 && part < 0; ++s) {
        auto in = OIIO::ImageInput::open(first);
        ASSERT_TRUE(in);
        if (!in->seek_subimage(s, 0)) break;
        if (in->spec().channel_name(0) == "ViewLayer.Diffuse Indirect.R") part = s;
    }
    ASSERT_GE(part, 0);
    const ExrImage direct = read_exr(first, part);
    std::vector<float> frame(direct.pixels.size());
    seq->get_frame(0, frame.data());
    EXPECT_EQ(frame, direct.pixels);
}
