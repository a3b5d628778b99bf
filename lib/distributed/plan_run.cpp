#include "distributed/plan_run.hpp"

#include <cstdint>
#include <filesystem>

#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"

namespace statfilter {

std::string name_plan_run(const std::string& text, const std::string& inputs, std::string* run) {
    uint64_t h = 1469598103934665603ull;  // FNV-1a, 64 bits: stable across builds and hosts
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    for (unsigned char c : inputs) h = (h ^ c) * 1099511628211ull;
    static const char digits[] = "0123456789abcdef";
    std::string name = "run-";
    for (int shift = 60; shift >= 0; shift -= 4) name += digits[(h >> shift) & 15];
    const size_t line = text.find("\n  \"work\": ");
    const size_t end = line == std::string::npos ? std::string::npos : text.find('\n', line + 1);
    if (end == std::string::npos) throw Error(Status::Internal, "a plan without a work directory line");
    if (run) *run = name;
    return text.substr(0, end + 1) + "  \"run\": \"" + name + "\",\n" + text.substr(end + 1);
}

std::string input_files_stamp(const std::string& pattern, const std::vector<int64_t>& frame_numbers) {
    namespace fs = std::filesystem;
    const FramePattern files(pattern);
    std::string stamp;
    for (const int64_t n : frame_numbers) {
        const std::string path = files.has_frame_token() ? files.format(n) : pattern;
        std::error_code size_error, time_error;
        const auto size = fs::file_size(path, size_error);
        const auto time = fs::last_write_time(path, time_error);
        stamp += path + " " + std::to_string(size_error ? 0 : size) + " " +
                 std::to_string(time_error ? 0 : static_cast<long long>(time.time_since_epoch().count())) + "\n";
        if (!files.has_frame_token()) break;
    }
    return stamp;
}

}  // namespace statfilter
