// Frame-sequence file patterns in oiiotool's conventions, and frame-range specs.
//   name.####.exr  name.#.exr  -> 4-digit padded frame numbers ('#' alone means 4 digits)
//   name.@@@.exr               -> one digit of padding per '@'
//   name.%04d.exr  name.%d.exr -> printf style
// A pattern without any of these names a single file (frame 1).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace statfilter {

class FramePattern {
public:
    explicit FramePattern(const std::string& pattern);

    bool has_frame_token() const { return has_token_; }
    int padding() const { return padding_; }
    // The file name of a frame (negative numbers keep their sign before the padded digits).
    std::string format(int64_t frame) const;
    // Frame numbers of the files on disk that match, ascending.
    std::vector<int64_t> scan() const;
    const std::string& text() const { return text_; }

private:
    std::string text_, prefix_, suffix_;
    int padding_ = 0;
    bool has_token_ = false;
};

// Parses "1-48", "1-10,12,20-30", "5" (a step is "1-100x2"). Throws Error(InvalidArgument).
std::vector<int64_t> parse_frame_spec(const std::string& spec);

// Formats ascending frame numbers compactly, e.g. {1,2,3,5} -> "1-3,5".
std::string format_frame_list(const std::vector<int64_t>& frames);

}  // namespace statfilter
