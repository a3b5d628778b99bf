// Files through the C ABI: bad input gets a clear error naming the file or argument, and a failed
// write leaves nothing behind (no frame, no hidden temporary file). NaN/Inf and half-range policy.
#include <statfilter/statfilter.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "capi_util.hpp"

using namespace statfilter_test;

namespace {

const sf_shape kShape = shape_of(3, 4, 5, 3);

// A sequence with channels R, G, B, frames first..first+F-1 and sample_value() data (or `value`).
Seq rgb_sequence(const sf_shape& shape = kShape, int64_t first_frame = 1,
                 const std::function<float(int64_t, int64_t, int64_t, int64_t)>& value = sample_value) {
    Seq seq = filled_sequence(shape, value);
    const char* names[] = {"R", "G", "B", "A"};
    for (int64_t c = 0; c < shape.channels && c < 4; ++c) EXPECT_SF_OK(sf_sequence_set_channel_name(seq.get(), c, names[c]));
    for (int64_t f = 0; f < shape.frames; ++f) EXPECT_SF_OK(sf_sequence_set_frame_number(seq.get(), f, first_frame + f));
    return seq;
}

void write_ok(sf_sequence seq, const std::string& pattern, sf_pixel_type type = SF_PIXEL_FLOAT) {
    const sf_write_options o = write_options(type);
    EXPECT_SF_OK(sf_sequence_write(seq, pattern.c_str(), &o));
}

// Reading must fail with `expected`, a message holding every fragment, and no sequence returned.
void expect_read_failure(const std::string& pattern, const char* channels, sf_status expected,
                         const std::vector<std::string>& fragments) {
    sf_read_options o;
    sf_read_options_init(&o);
    o.channels = channels;
    int dummy = 0;
    sf_sequence out = reinterpret_cast<sf_sequence>(&dummy);
    expect_failure(sf_sequence_read(pattern.c_str(), &o, &out), expected, fragments, pattern.c_str());
    EXPECT_EQ(out, nullptr);
}

// Writing must fail with `expected` and a message holding every fragment, and leave `dir` empty.
void expect_write_failure(sf_sequence seq, const std::string& pattern, const sf_write_options& options,
                          sf_status expected, const std::vector<std::string>& fragments, const fs::path& dir) {
    expect_failure(sf_sequence_write(seq, pattern.c_str(), &options), expected, fragments, pattern.c_str());
    EXPECT_EQ(files_in(dir), std::vector<std::string>{}) << "after failing to write " << pattern;
}

}  // namespace

// ---- reading bad input -------------------------------------------------------------------------

TEST(BadInput, GapInTheSequenceListsTheMissingFrames) {
    TempDir dir;
    Seq seq = rgb_sequence(shape_of(8, 2, 3, 3));
    write_ok(seq.get(), dir.file("g.####.exr"));
    for (const char* name : {"g.0003.exr", "g.0006.exr", "g.0007.exr"}) fs::remove(dir.path() / name);
    expect_read_failure(dir.file("g.####.exr"), nullptr, SF_ERROR_NOT_FOUND, {"g.####.exr", "3,6-7", "missing"});

    // Choosing the frames explicitly skips the gap.
    sf_read_options o;
    sf_read_options_init(&o);
    o.frames = "1-2,4-5,8";
    sf_sequence out = nullptr;
    ASSERT_SF_OK(sf_sequence_read(dir.file("g.####.exr").c_str(), &o, &out));
    Seq owned(out);
    EXPECT_EQ(frame_numbers(out), (std::vector<int64_t>{1, 2, 4, 5, 8}));
    // ... but asking for a frame that is not there names it.
    o.frames = "1-3";
    expect_failure(sf_sequence_read(dir.file("g.####.exr").c_str(), &o, &out), SF_ERROR_NOT_FOUND, {"g.0003.exr"});
}

TEST(BadInput, FramesOfDifferentSizes) {
    TempDir dir;
    write_ok(rgb_sequence(shape_of(3, 4, 5, 3)).get(), dir.file("s.####.exr"));
    write_ok(rgb_sequence(shape_of(1, 3, 2, 3), 4).get(), dir.file("s.####.exr"));
    expect_read_failure(dir.file("s.####.exr"), nullptr, SF_ERROR_INVALID_ARGUMENT,
                        {"s.0004.exr", "2 x 3", "first frame is 5 x 4"});
}

TEST(BadInput, FrameMissingAChannelOfTheFirst) {
    TempDir dir;
    write_ok(rgb_sequence(shape_of(2, 4, 5, 3)).get(), dir.file("m.####.exr"));
    write_ok(rgb_sequence(shape_of(1, 4, 5, 2), 3).get(), dir.file("m.####.exr"));  // R, G only
    expect_read_failure(dir.file("m.####.exr"), nullptr, SF_ERROR_NOT_FOUND, {"m.0003.exr", "'B'"});
    expect_read_failure(dir.file("m.####.exr"), "B", SF_ERROR_NOT_FOUND, {"m.0003.exr", "'B'"});
    // Only the channels present everywhere: fine.
    sf_status status = SF_OK;
    Seq rg = read_sequence(dir.file("m.####.exr"), "R,G", &status);
    EXPECT_EQ(status, SF_OK) << sf_last_error();
}

TEST(BadInput, TruncatedFile) {
    TempDir dir;
    Seq seq = rgb_sequence(shape_of(3, 48, 64, 3));
    for (const char* compression : {"zip", "none"}) {
        const std::string pattern = dir.file(std::string(compression) + ".####.exr");
        sf_write_options o = write_options();
        o.compression = compression;
        ASSERT_SF_OK(sf_sequence_write(seq.get(), pattern.c_str(), &o));
        truncate_to_half(dir.file(std::string(compression) + ".0002.exr"));
        expect_read_failure(pattern, nullptr, SF_ERROR_IO, {std::string(compression) + ".0002.exr"});
    }
}

TEST(BadInput, FileThatIsNotAnImage) {
    TempDir dir;
    write_ok(rgb_sequence(shape_of(2, 4, 5, 3)).get(), dir.file("n.####.exr"));
    write_text_file(dir.file("n.0003.exr"), "this is a text file, not an OpenEXR image\n");
    expect_read_failure(dir.file("n.####.exr"), nullptr, SF_ERROR_IO, {"n.0003.exr"});
    write_text_file(dir.file("text.exr"), "plain text");
    expect_read_failure(dir.file("text.exr"), nullptr, SF_ERROR_IO, {"text.exr"});
    write_text_file(dir.file("empty.exr"), "");
    expect_read_failure(dir.file("empty.exr"), nullptr, SF_ERROR_IO, {"empty.exr"});
}

TEST(BadInput, MissingChannelOrLayerListsTheAvailableOnes) {
    TempDir dir;
    write_ok(rgb_sequence().get(), dir.file("c.####.exr"));
    expect_read_failure(dir.file("c.####.exr"), "A", SF_ERROR_NOT_FOUND, {"'A'", "c.0001.exr", "R, G, B"});
    expect_read_failure(dir.file("c.####.exr"), "R,Z", SF_ERROR_NOT_FOUND, {"'Z'", "R, G, B"});
    expect_read_failure(dir.file("c.####.exr"), "ViewLayer.Diffuse Indirect", SF_ERROR_NOT_FOUND,
                        {"'ViewLayer.Diffuse Indirect'", "R, G, B"});
}

TEST(BadInput, PatternWithNoFrames) {
    TempDir dir;
    expect_read_failure(dir.file("nothing.####.exr"), nullptr, SF_ERROR_NOT_FOUND, {"nothing.####.exr"});
    expect_read_failure(dir.file("still.exr"), nullptr, SF_ERROR_NOT_FOUND, {"still.exr"});
    expect_read_failure(dir.file("no-dir/a.####.exr"), nullptr, SF_ERROR_NOT_FOUND, {"no-dir/a.####.exr"});
    expect_read_failure("", nullptr, SF_ERROR_INVALID_ARGUMENT, {"pattern"});
}

TEST(BadInput, BadFrameSpecNamesIt) {
    TempDir dir;
    write_ok(rgb_sequence().get(), dir.file("f.####.exr"));
    sf_read_options o;
    sf_read_options_init(&o);
    sf_sequence out = nullptr;
    for (const char* spec : {"5-1", "1,", "abc"}) {
        o.frames = spec;
        expect_failure(sf_sequence_read(dir.file("f.####.exr").c_str(), &o, &out), SF_ERROR_INVALID_ARGUMENT,
                       {std::string("'") + spec + "'"});
        EXPECT_EQ(out, nullptr);
    }
}

// ---- writing: failures leave nothing -----------------------------------------------------------

TEST(BadOutput, MissingDirectoryIsCreated) {
    TempDir dir;
    Seq seq = rgb_sequence();
    const sf_write_options options = write_options();
    ASSERT_EQ(sf_sequence_write(seq.get(), dir.file("new/dir/o.####.exr").c_str(), &options), SF_OK) << sf_last_error();
    EXPECT_TRUE(fs::exists(dir.path() / "new" / "dir" / "o.0001.exr"));
}

TEST(BadOutput, DirectoryThatCannotBeCreated) {
    TempDir dir;
    { std::ofstream(dir.file("plain")) << "a file, not a directory"; }
    Seq seq = rgb_sequence();
    const sf_write_options options = write_options();
    const std::string pattern = dir.file("plain/sub/o.####.exr");
    expect_failure(sf_sequence_write(seq.get(), pattern.c_str(), &options), SF_ERROR_IO, {"plain/sub", "cannot be created"},
                   pattern.c_str());
    EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"plain"});
}

TEST(BadOutput, ReadOnlyDirectory) {
    if (running_as_root()) GTEST_SKIP() << "root can write into read-only directories";
    TempDir dir;
    const fs::path ro = dir.path() / "ro";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    Seq seq = rgb_sequence();
    expect_write_failure(seq.get(), (ro / "o.####.exr").string(), write_options(), SF_ERROR_IO,
                         {"ro", "not writable"}, ro);
}

TEST(BadOutput, PatternWithoutFrameTokenForManyFrames) {
    TempDir dir;
    Seq seq = rgb_sequence();
    expect_write_failure(seq.get(), dir.file("out.exr"), write_options(), SF_ERROR_INVALID_ARGUMENT,
                         {"out.exr", "frame token", "3 frames"}, dir.path());
    // One frame needs no token.
    Seq one = rgb_sequence(shape_of(1, 4, 5, 3));
    write_ok(one.get(), dir.file("out.exr"));
    EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"out.exr"});
}

TEST(BadOutput, UnknownCompressionOrPixelType) {
    TempDir dir;
    Seq seq = rgb_sequence();
    sf_write_options o = write_options();
    o.compression = "lzma";
    expect_write_failure(seq.get(), dir.file("o.####.exr"), o, SF_ERROR_INVALID_ARGUMENT, {"lzma", "zip"}, dir.path());
    o = write_options();
    o.pixel_type = static_cast<sf_pixel_type>(7);
    expect_write_failure(seq.get(), dir.file("o.####.exr"), o, SF_ERROR_INVALID_ARGUMENT, {"pixel_type"}, dir.path());
}

TEST(BadOutput, IncompleteColourConversion) {
    TempDir dir;
    Seq seq = rgb_sequence();
    sf_write_options o = write_options();
    o.colorspace_in = "linear";  // no output colour space
    expect_write_failure(seq.get(), dir.file("o.####.exr"), o, SF_ERROR_INVALID_ARGUMENT, {"colour"}, dir.path());
}

TEST(BadOutput, CancelBeforeTheFirstFrame) {
    TempDir dir;
    Seq seq = rgb_sequence();
    sf_write_options o = write_options();
    o.progress = [](void*, double, const char*) { return 1; };
    expect_write_failure(seq.get(), dir.file("o.####.exr"), o, SF_ERROR_CANCELLED, {"cancel"}, dir.path());
}

namespace {

// A failure after some frames were written: the header promises no half-written frame (each is
// renamed into place when complete), not an all-or-nothing sequence. So: no hidden temporary file,
// nothing but the expected names, and every frame that is there reads back whole.
void expect_only_complete_frames(const fs::path& dir, const std::vector<std::string>& allowed) {
    for (const std::string& name : files_in(dir)) {
        EXPECT_NE(std::find(allowed.begin(), allowed.end(), name), allowed.end()) << "unexpected file " << name;
        if (!fs::is_regular_file(dir / name)) continue;
        sf_status status = SF_OK;
        Seq frame = read_sequence((dir / name).string(), nullptr, &status);
        EXPECT_EQ(status, SF_OK) << name << " is not a complete image: " << sf_last_error();
    }
}

}  // namespace

TEST(BadOutput, FailureMidSequenceLeavesNoTemporaryOrPartialFile) {
    TempDir dir;
    Seq seq = rgb_sequence();
    // Frame 2's name is taken by a directory: its rename fails after the data was written.
    fs::create_directory(dir.path() / "o.0002.exr");
    const sf_write_options o = write_options();
    expect_failure(sf_sequence_write(seq.get(), dir.file("o.####.exr").c_str(), &o), SF_ERROR_IO, {"o.0002.exr"});
    EXPECT_TRUE(fs::is_empty(dir.path() / "o.0002.exr"));
    expect_only_complete_frames(dir.path(), {"o.0001.exr", "o.0002.exr"});
}

TEST(BadOutput, CancelMidSequenceLeavesNoTemporaryOrPartialFile) {
    TempDir dir;
    Seq seq = rgb_sequence();
    int calls = 0;
    sf_write_options o = write_options();
    o.progress = [](void* user, double, const char*) { return ++*static_cast<int*>(user) == 2 ? 1 : 0; };
    o.progress_user = &calls;
    expect_failure(sf_sequence_write(seq.get(), dir.file("o.####.exr").c_str(), &o), SF_ERROR_CANCELLED, {"cancel"});
    EXPECT_EQ(calls, 2);
    expect_only_complete_frames(dir.path(), {"o.0001.exr"});
}

// ---- half range, NaN and Inf -------------------------------------------------------------------

TEST(Numeric, HalfOverflowWritesNothing) {
    for (float big : {1e6f, -1e6f, 65520.0f}) {
        TempDir dir;
        // The bad value is in the last frame: the earlier frames must not be written either.
        Seq seq = rgb_sequence(kShape, 1, [big](int64_t f, int64_t y, int64_t x, int64_t c) {
            return f == 2 && y == 1 && x == 2 && c == 1 ? big : sample_value(f, y, x, c);
        });
        expect_write_failure(seq.get(), dir.file("h.####.exr"), write_options(SF_PIXEL_HALF), SF_ERROR_NUMERIC,
                             {"frame 3", "'G'", "65504"}, dir.path());
    }
}

TEST(Numeric, HalfOverflowClampsWhenAsked) {
    TempDir dir;
    Seq seq = rgb_sequence(kShape, 1, [](int64_t f, int64_t y, int64_t x, int64_t c) {
        if (f == 2 && y == 1 && x == 2) return c == 0 ? 1e6f : c == 1 ? -1e6f : 65504.0f;
        return sample_value(f, y, x, c);
    });
    sf_write_options o = write_options(SF_PIXEL_HALF);
    o.half_overflow = 1;
    ASSERT_SF_OK(sf_sequence_write(seq.get(), dir.file("h.####.exr").c_str(), &o));
    sf_status status = SF_OK;
    Seq back = read_sequence(dir.file("h.####.exr"), nullptr, &status);
    ASSERT_EQ(status, SF_OK) << sf_last_error();
    float* data = nullptr;
    sf_strides st{};
    ASSERT_SF_OK(sf_sequence_data(back.get(), &data, &st));
    EXPECT_EQ(*sample_at(data, st, 2, 1, 2, 0), 65504.0f);
    EXPECT_EQ(*sample_at(data, st, 2, 1, 2, 1), -65504.0f);
    EXPECT_EQ(*sample_at(data, st, 2, 1, 2, 2), 65504.0f);
    EXPECT_EQ(*sample_at(data, st, 0, 3, 4, 2), sample_value(0, 3, 4, 2));  // exact in half
    sf_channel_stats stats{};
    ASSERT_SF_OK(sf_sequence_channel_stats(back.get(), 0, &stats));
    EXPECT_EQ(stats.inf_count, 0);
    EXPECT_EQ(stats.max, 65504.0);
}

TEST(Numeric, NanAndInfRoundTripAndAreCounted) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    auto value = [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        if (c == 0 && f == 0 && y == 0) return x == 0 ? nan : x == 1 ? inf : x == 2 ? -inf : x == 3 ? nan : 2.0f;
        return c == 0 ? (f == 1 ? -3.0f : 2.0f) : sample_value(f, y, x, c);
    };
    for (sf_pixel_type type : {SF_PIXEL_FLOAT, SF_PIXEL_HALF}) {
        TempDir dir;
        Seq seq = rgb_sequence(kShape, 1, value);
        write_ok(seq.get(), dir.file("n.####.exr"), type);  // non-finite values are no half-range error
        sf_status status = SF_OK;
        Seq back = read_sequence(dir.file("n.####.exr"), nullptr, &status);
        ASSERT_EQ(status, SF_OK) << sf_last_error();
        float* data = nullptr;
        sf_strides st{};
        ASSERT_SF_OK(sf_sequence_data(back.get(), &data, &st));
        EXPECT_TRUE(std::isnan(*sample_at(data, st, 0, 0, 0, 0)));
        EXPECT_EQ(*sample_at(data, st, 0, 0, 1, 0), inf);
        EXPECT_EQ(*sample_at(data, st, 0, 0, 2, 0), -inf);
        EXPECT_TRUE(std::isnan(*sample_at(data, st, 0, 0, 3, 0)));

        sf_channel_stats stats{};
        ASSERT_SF_OK(sf_sequence_channel_stats(back.get(), 0, &stats));
        EXPECT_EQ(stats.nan_count, 2);
        EXPECT_EQ(stats.inf_count, 2);
        EXPECT_EQ(stats.min, -3.0);  // over finite samples only
        EXPECT_EQ(stats.max, 2.0);
        EXPECT_TRUE(std::isfinite(stats.mean));
        ASSERT_SF_OK(sf_sequence_channel_stats(back.get(), 1, &stats));
        EXPECT_EQ(stats.nan_count + stats.inf_count, 0);
    }
}

TEST(Numeric, FloatKeepsWhatHalfCannot) {
    TempDir dir;
    Seq seq = rgb_sequence(kShape, 1, [](int64_t f, int64_t y, int64_t x, int64_t c) {
        return sample_value(f, y, x, c) * 1e30f;
    });
    write_ok(seq.get(), dir.file("f.####.exr"), SF_PIXEL_FLOAT);
    sf_status status = SF_OK;
    Seq back = read_sequence(dir.file("f.####.exr"), nullptr, &status);
    ASSERT_EQ(status, SF_OK) << sf_last_error();
    EXPECT_EQ(samples_of(back.get()), samples_of(seq.get()));
}

// ---- round trips through the C ABI ---------------------------------------------------------------

TEST(CapiIO, WrappedPlanarSequenceRoundTrip) {
    TempDir dir;
    const int64_t kF = sizeof(float);
    std::vector<float> planar(static_cast<size_t>(sample_count(kShape)));
    const sf_strides st{kF * kShape.width * kShape.height * kShape.frames, kF, kF * kShape.width,
                        kF * kShape.width * kShape.height};
    for_each_sample(kShape, [&](int64_t f, int64_t y, int64_t x, int64_t c) {
        *sample_at(planar.data(), st, f, y, x, c) = sample_value(f, y, x, c);
    });
    sf_sequence raw = nullptr;
    ASSERT_SF_OK(sf_sequence_wrap(planar.data(), kShape, st, &raw));
    Seq seq(raw);
    // "Z" is a depth channel to OpenImageIO, which lists it first when reading: EXR keeps no channel
    // order, so a channel is found by its name, and its data must follow the name.
    ASSERT_SF_OK(sf_sequence_set_channel_name(raw, 2, "Z"));
    ASSERT_SF_OK(sf_sequence_set_frame_number(raw, 0, 41));  // 41, 2, 3: not ascending, still written
    write_ok(raw, dir.file("w.####.exr"));
    EXPECT_EQ(files_in(dir.path()), (std::vector<std::string>{"w.0002.exr", "w.0003.exr", "w.0041.exr"}));

    sf_status status = SF_OK;
    Seq back = read_sequence(dir.file("w.%04d.exr"), nullptr, &status);
    ASSERT_TRUE(status == SF_ERROR_NOT_FOUND) << "frames 4-40 are a gap";
    sf_read_options o;
    sf_read_options_init(&o);
    o.frames = "41";
    sf_sequence one = nullptr;
    ASSERT_SF_OK(sf_sequence_read(dir.file("w.####.exr").c_str(), &o, &one));
    Seq owned(one);
    const std::vector<std::string> written = {"C0", "C1", "Z"};
    int64_t source[3];  // the written channel each read channel holds
    for (int64_t c = 0; c < 3; ++c) {
        const auto it = std::find(written.begin(), written.end(), channel_name(one, c));
        ASSERT_NE(it, written.end()) << channel_name(one, c);
        source[c] = it - written.begin();
    }
    const std::vector<float> got = samples_of(one);
    size_t i = 0;
    for_each_sample(shape_of(1, kShape.height, kShape.width, kShape.channels),
                    [&](int64_t f, int64_t y, int64_t x, int64_t c) {
                        ASSERT_EQ(got[i++], sample_value(f, y, x, source[c])) << "channel " << channel_name(one, c);
                    });
}

TEST(CapiIO, ReadProgressAndCancel) {
    TempDir dir;
    write_ok(rgb_sequence().get(), dir.file("r.####.exr"));
    struct Log {
        std::vector<double> fractions;
        bool cancel = false;
    } log;
    sf_read_options o;
    sf_read_options_init(&o);
    o.progress = [](void* user, double fraction, const char*) {
        auto* l = static_cast<Log*>(user);
        l->fractions.push_back(fraction);
        return l->cancel ? 1 : 0;
    };
    o.progress_user = &log;
    sf_sequence out = nullptr;
    ASSERT_SF_OK(sf_sequence_read(dir.file("r.####.exr").c_str(), &o, &out));
    Seq owned(out);
    ASSERT_FALSE(log.fractions.empty());
    for (double v : log.fractions) EXPECT_TRUE(v >= 0 && v <= 1) << v;
    EXPECT_EQ(log.fractions.back(), 1.0);

    log.cancel = true;
    sf_sequence cancelled = nullptr;
    expect_failure(sf_sequence_read(dir.file("r.####.exr").c_str(), &o, &cancelled), SF_ERROR_CANCELLED, {"cancel"});
    EXPECT_EQ(cancelled, nullptr);
}

TEST(ChannelSelection, NamesWhatADefaultOrAListTakes) {
    TempDir dir;
    Seq seq = filled_sequence(shape_of(1, 2, 3, 4), sample_value);
    const char* names[] = {"ViewLayer.Combined.R", "ViewLayer.Combined.A", "ViewLayer.Normal.X", "ViewLayer.Emit.R"};
    for (int64_t c = 0; c < 4; ++c) EXPECT_SF_OK(sf_sequence_set_channel_name(seq.get(), c, names[c]));
    write_ok(seq.get(), dir.file("l.0001.exr"));
    auto selection = [&](const char* channels) {
        size_t needed = 0;
        EXPECT_SF_OK(sf_channel_selection(dir.file("l.0001.exr").c_str(), channels, nullptr, 0, &needed));
        std::string text(needed, '\0');
        EXPECT_SF_OK(sf_channel_selection(dir.file("l.0001.exr").c_str(), channels, text.data(), needed, &needed));
        return std::string(text.c_str());
    };
    const std::string by_default = selection(nullptr);
    EXPECT_NE(by_default.find("ViewLayer.Combined.R"), std::string::npos) << by_default;
    EXPECT_NE(by_default.find("ViewLayer.Emit.R"), std::string::npos) << by_default;
    EXPECT_EQ(by_default.find("Normal"), std::string::npos) << by_default;
    EXPECT_EQ(by_default.find(".A"), std::string::npos) << by_default;
    EXPECT_EQ(selection("ViewLayer.Normal"), "ViewLayer.Normal.X");
    const std::string all = selection("*");
    EXPECT_EQ(std::count(all.begin(), all.end(), ','), 3) << all;
}

TEST(FrameWindows, OfASequenceNotReadFromFilesAreItsOwnSize) {
    Seq seq = rgb_sequence();
    sf_window data{}, display{}, file_data{};
    ASSERT_SF_OK(sf_sequence_frame_windows(seq.get(), 1, &data, &display, &file_data));
    EXPECT_EQ(data.width, 5);
    EXPECT_EQ(data.height, 4);
    EXPECT_EQ(display.width, 5);
    EXPECT_EQ(file_data.height, 4);
    EXPECT_EQ(sf_sequence_frame_windows(seq.get(), 3, &data, nullptr, nullptr), SF_ERROR_INVALID_ARGUMENT);
}
