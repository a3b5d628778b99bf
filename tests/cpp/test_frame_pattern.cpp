// Frame patterns (oiiotool conventions), scanning a directory for frames, and frame-range specs.
#include <gtest/gtest.h>

#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"
#include "test_util.hpp"

using namespace statfilter;
using statfilter_test::TempDir;
using statfilter_test::write_text_file;

namespace {

struct FormatCase {
    const char* pattern;
    int padding;
    int64_t frame;
    const char* expected;
};

class FramePatternFormat : public ::testing::TestWithParam<FormatCase> {};

// Creates empty files with these names in dir.
void touch(const TempDir& dir, std::initializer_list<const char*> names) {
    for (const char* n : names) write_text_file(dir.file(n), "");
}

}  // namespace

TEST_P(FramePatternFormat, FormatsFrameNumbers) {
    const FormatCase& c = GetParam();
    const FramePattern p(c.pattern);
    EXPECT_TRUE(p.has_frame_token());
    EXPECT_EQ(p.padding(), c.padding);
    EXPECT_EQ(p.format(c.frame), c.expected);
}

INSTANTIATE_TEST_SUITE_P(
    Tokens, FramePatternFormat,
    ::testing::Values(FormatCase{"a.####.exr", 4, 7, "a.0007.exr"},     // one '#' per digit
                      FormatCase{"a.#.exr", 4, 7, "a.0007.exr"},        // a lone '#' means 4 digits
                      FormatCase{"a.@@.exr", 2, 7, "a.07.exr"},         // one '@' per digit
                      FormatCase{"a.@.exr", 1, 7, "a.7.exr"},
                      FormatCase{"a.%04d.exr", 4, 7, "a.0007.exr"},
                      FormatCase{"a.%d.exr", 0, 7, "a.7.exr"},
                      FormatCase{"a.####.exr", 4, 12345, "a.12345.exr"},  // more digits than padding
                      FormatCase{"a.%06d.exr", 6, 42, "a.000042.exr"},
                      FormatCase{"shots/sh010/beauty.####.exr", 4, 1, "shots/sh010/beauty.0001.exr"}));

TEST(FramePattern, NoTokenNamesOneFile) {
    const FramePattern p("dir/still.exr");
    EXPECT_FALSE(p.has_frame_token());
    EXPECT_EQ(p.format(1), "dir/still.exr");
    EXPECT_EQ(p.format(99), "dir/still.exr");
}

TEST(FramePattern, TokensInDirectoryNamesAreLiteral) {
    const FramePattern p("renders#2/v@1/a.%03d.exr");
    EXPECT_TRUE(p.has_frame_token());
    EXPECT_EQ(p.format(5), "renders#2/v@1/a.005.exr");
    const FramePattern none("renders#2/a.exr");
    EXPECT_FALSE(none.has_frame_token());
}

TEST(FramePattern, RejectsEmptyAndDoubleTokens) {
    EXPECT_THROW(FramePattern(""), Error);
    EXPECT_THROW(FramePattern("a.####.@@.exr"), Error);
}

// Wide padding is written in full (no fixed-size buffer truncates it) and found again by a scan;
// an absurd width is a clear error, never an exception from std::stoi.
TEST(FramePattern, WidePaddingIsNeverTruncated) {
    const FramePattern p("o.%040d.exr");
    EXPECT_EQ(p.padding(), 40);
    EXPECT_EQ(p.format(7), "o." + std::string(39, '0') + "7.exr");
    EXPECT_NE(p.format(1), p.format(2));
    EXPECT_EQ(FramePattern("o.%064d.exr").format(-3), "o.-" + std::string(62, '0') + "3.exr");
    TempDir dir;
    const FramePattern in_dir(dir.file("o.%040d.exr"));
    write_text_file(in_dir.format(1), "");
    write_text_file(in_dir.format(123456789012345678), "");
    EXPECT_EQ(in_dir.scan(), (std::vector<int64_t>{1, 123456789012345678}));
}

TEST(FramePattern, AbsurdPaddingIsRefused) {
    const std::vector<std::string> patterns = {"a.%99999999999d.exr", "a.%65d.exr", "a.%0100d.exr",
                                               "a." + std::string(65, '#') + ".exr", "a." + std::string(1000, '@') + ".exr"};
    for (const std::string& pattern : patterns) {
        try {
            FramePattern p(pattern);
            ADD_FAILURE() << pattern << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("more than 64 digits"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(FramePattern("a.%064d.exr").padding(), 64);
    EXPECT_EQ(FramePattern("a.%0000d.exr").padding(), 0);
}

TEST(FramePatternScan, OnlyTheMatchingPaddingIsFound) {
    TempDir dir;
    touch(dir, {"a.0001.exr", "a.0002.exr", "a.1.exr", "a.3.exr", "a.03.exr", "a.0004.exr.bak", "b.0005.exr",
                "a.00x6.exr", "a.10000.exr"});
    EXPECT_EQ(FramePattern(dir.file("a.####.exr")).scan(), (std::vector<int64_t>{1, 2, 10000}));
    EXPECT_EQ(FramePattern(dir.file("a.#.exr")).scan(), (std::vector<int64_t>{1, 2, 10000}));
    EXPECT_EQ(FramePattern(dir.file("a.%04d.exr")).scan(), (std::vector<int64_t>{1, 2, 10000}));
    EXPECT_EQ(FramePattern(dir.file("a.%d.exr")).scan(), (std::vector<int64_t>{1, 3, 10000}));
    EXPECT_EQ(FramePattern(dir.file("a.@@.exr")).scan(), (std::vector<int64_t>{3, 10000}));
    EXPECT_EQ(FramePattern(dir.file("a.@.exr")).scan(), (std::vector<int64_t>{1, 3, 10000}));
}

TEST(FramePatternScan, FramesBeyond9999) {
    TempDir dir;
    touch(dir, {"a.9998.exr", "a.9999.exr", "a.10000.exr", "a.10001.exr"});
    EXPECT_EQ(FramePattern(dir.file("a.####.exr")).scan(), (std::vector<int64_t>{9998, 9999, 10000, 10001}));
}

TEST(FramePatternScan, NegativeFrames) {
    TempDir dir;
    touch(dir, {"a.-001.exr", "a.0000.exr", "a.0001.exr"});
    const FramePattern p(dir.file("a.####.exr"));
    EXPECT_EQ(p.scan(), (std::vector<int64_t>{-1, 0, 1}));
    EXPECT_EQ(p.format(-1), dir.file("a.-001.exr"));
}

TEST(FramePatternScan, DirectoriesInThePath) {
    TempDir dir;
    std::filesystem::create_directories(dir.path() / "shot 1" / "v2");
    touch(dir, {"shot 1/v2/beauty.0010.exr", "shot 1/v2/beauty.0011.exr", "shot 1/beauty.0012.exr"});
    // A directory whose name matches the pattern is not a frame.
    std::filesystem::create_directories(dir.path() / "shot 1" / "v2" / "beauty.0013.exr");
    EXPECT_EQ(FramePattern(dir.file("shot 1/v2/beauty.####.exr")).scan(), (std::vector<int64_t>{10, 11}));
    EXPECT_EQ(FramePattern(dir.file("shot 1/beauty.####.exr")).scan(), (std::vector<int64_t>{12}));
}

TEST(FramePatternScan, NoTokenAndNothingFound) {
    TempDir dir;
    touch(dir, {"still.exr"});
    EXPECT_EQ(FramePattern(dir.file("still.exr")).scan(), (std::vector<int64_t>{1}));
    EXPECT_TRUE(FramePattern(dir.file("other.exr")).scan().empty());
    EXPECT_TRUE(FramePattern(dir.file("a.####.exr")).scan().empty());
    EXPECT_TRUE(FramePattern(dir.file("no such dir/a.####.exr")).scan().empty());
}

TEST(FrameSpec, Ranges) {
    std::vector<int64_t> one_to_48;
    for (int64_t f = 1; f <= 48; ++f) one_to_48.push_back(f);
    EXPECT_EQ(parse_frame_spec("1-48"), one_to_48);
    EXPECT_EQ(parse_frame_spec("1-10,12"), (std::vector<int64_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 12}));
    EXPECT_EQ(parse_frame_spec("1-10x3"), (std::vector<int64_t>{1, 4, 7, 10}));
    EXPECT_EQ(parse_frame_spec("5"), (std::vector<int64_t>{5}));
    // Overlaps collapse and the result is ascending.
    EXPECT_EQ(parse_frame_spec("8,2-4,3"), (std::vector<int64_t>{2, 3, 4, 8}));
}

TEST(FrameSpec, Errors) {
    for (const char* spec : {"", "5-1", "1,", "abc", "1-", "-", "1-10x0", "1;2", ",1"}) {
        try {
            parse_frame_spec(spec);
            ADD_FAILURE() << "'" << spec << "' was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::InvalidArgument) << spec;
            // The message quotes the spec so a user sees which argument was wrong.
            EXPECT_NE(std::string(e.what()).find(std::string("'") + spec + "'"), std::string::npos) << e.what();
        }
    }
}

TEST(FrameSpec, FormatFrameList) {
    EXPECT_EQ(format_frame_list({1, 2, 3, 5}), "1-3,5");
    EXPECT_EQ(format_frame_list({4}), "4");
    EXPECT_EQ(format_frame_list({}), "");
    EXPECT_EQ(format_frame_list({1, 3, 4, 5, 9, 10}), "1,3-5,9-10");
}
