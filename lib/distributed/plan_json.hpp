// The small JSON pieces a plan writer spells out (lib/distributed/tile_plan.cpp, detect_plan.cpp).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"

namespace statfilter {

inline std::string range_json(int64_t a, int64_t b) { return "[" + std::to_string(a) + ", " + std::to_string(b) + "]"; }

// The plan's text with its run named: "run": "run-" and 16 hex digits of a hash of the text and of
// `inputs` (what identifies the input files' contents: input_files_stamp), after its "work" line.
// The same request on the same, unchanged frames makes the same run (a task run again finds its
// files); other options, or frames rendered again, make another. Returns the run through `run`.
inline std::string name_plan_run(const std::string& text, const std::string& inputs, std::string* run) {
    uint64_t h = 1469598103934665603ull;  // FNV-1a, 64 bits: stable across builds and hosts
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    for (unsigned char c : inputs) h = (h ^ c) * 1099511628211ull;
    static const char digits[] = "0123456789abcdef";
    std::string name = "run-";
    for (int shift = 60; shift >= 0; shift -= 4) name += digits[(h >> shift) & 15];
    const std::string key = "\n  \"work\": ";
    const size_t line = text.find(key);
    const size_t end = line == std::string::npos ? std::string::npos : text.find('\n', line + 1);
    if (end == std::string::npos) throw Error(Status::Internal, "a plan without a work directory line");
    if (run) *run = name;
    return text.substr(0, end + 1) + "  \"run\": \"" + name + "\",\n" + text.substr(end + 1);
}

// Each input frame's size and modification time (nanoseconds), for name_plan_run: a frame written
// again changes its run.
inline std::string input_files_stamp(const std::string& pattern, const std::vector<int64_t>& frame_numbers) {
    namespace fs = std::filesystem;
    const FramePattern files(pattern);
    std::string stamp;
    for (const int64_t n : frame_numbers) {
        const std::string path = files.has_frame_token() ? files.format(n) : pattern;
        std::error_code ec;
        const auto size = fs::file_size(path, ec);
        const auto time = fs::last_write_time(path, ec);
        stamp += path + " " + std::to_string(ec ? 0 : size) + " " +
                 std::to_string(ec ? 0 : time.time_since_epoch().count()) + "\n";
        if (!files.has_frame_token()) break;
    }
    return stamp;
}

inline std::string list_json(const std::vector<int64_t>& v) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    return s + "]";
}

}  // namespace statfilter
