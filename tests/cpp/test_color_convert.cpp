// OpenColorIO conversion on read and write, with a test config whose conversion is exact (x2).
#include <gtest/gtest.h>

#include "statfilter/error.hpp"
#include "statfilter/sequence_io.hpp"
#include "test_util.hpp"

using namespace statfilter;
using namespace statfilter_test;

namespace {

const std::string kConfig = STATFILTER_TEST_DATA "/scale2.ocio";

std::unique_ptr<Sequence> ramp(int64_t channels) {
    auto seq = std::make_unique<Sequence>(Shape{2, 3, 4, channels});
    for (int64_t f = 0; f < 2; ++f)
        for (int64_t y = 0; y < 3; ++y)
            for (int64_t x = 0; x < 4; ++x)
                for (int64_t c = 0; c < channels; ++c) seq->at(f, y, x, c) = 0.25f * (f + y + x + c);
    seq->channel_names() = channels == 3 ? std::vector<std::string>{"R", "G", "B"}
                                         : std::vector<std::string>{"R", "G", "B", "A"};
    return seq;
}

}  // namespace

TEST(ColorConvert, ConvertsOnWriteAndBackOnRead) {
    TempDir dir;
    const auto seq = ramp(3);
    WriteOptions w;
    w.half = false;
    w.color = {kConfig, "linear", "doubled"};
    write_sequence(*seq, dir.file("c.####.exr"), w);

    // Read as stored: doubled.
    const auto stored = read_sequence(dir.file("c.####.exr"), ReadOptions());
    EXPECT_FLOAT_EQ(stored->at(1, 2, 3, 2), 2 * seq->at(1, 2, 3, 2));
    // Read converting back: the original values.
    ReadOptions r;
    r.color = {kConfig, "doubled", "linear"};
    const auto back = read_sequence(dir.file("c.####.exr"), r);
    for (int64_t c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(back->at(1, 2, 3, c), seq->at(1, 2, 3, c));
}

TEST(ColorConvert, AlphaIsLeftAlone) {
    TempDir dir;
    const auto seq = ramp(4);
    WriteOptions w;
    w.half = false;
    w.color = {kConfig, "linear", "doubled"};
    write_sequence(*seq, dir.file("a.####.exr"), w);
    const auto stored = read_sequence(dir.file("a.####.exr"), ReadOptions());
    EXPECT_FLOAT_EQ(stored->at(1, 1, 1, 0), 2 * seq->at(1, 1, 1, 0));
    EXPECT_FLOAT_EQ(stored->at(1, 1, 1, 3), seq->at(1, 1, 1, 3));
}

TEST(ColorConvert, BadConversionsFailBeforeWriting) {
    TempDir dir;
    auto expect_error = [&](const ColorConversion& conv, int64_t channels, const std::string& needle) {
        WriteOptions w;
        w.color = conv;
        try {
            write_sequence(*ramp(channels == 4 ? 4 : 3), dir.file("b.####.exr"), w);
            ADD_FAILURE() << "accepted " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
        EXPECT_TRUE(files_in(dir.path()).empty());
    };
    expect_error({kConfig, "linear", "nonexistent"}, 3, "nonexistent");
    expect_error({kConfig, "linear", ""}, 3, "both");
    expect_error({dir.file("missing.ocio"), "linear", "doubled"}, 3, "OpenColorIO");
}
