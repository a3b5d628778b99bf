#include "statfilter/frame_pattern.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <set>

#include "statfilter/error.hpp"

namespace fs = std::filesystem;

namespace statfilter {

namespace {

// Far more digits than any frame number has, and short enough for a file name (NAME_MAX 255).
constexpr size_t kMaxPadding = 64;

int checked_padding(const std::string& pattern, size_t digits) {
    if (digits > kMaxPadding)
        throw Error(Status::InvalidArgument, "pattern '" + pattern + "' pads frame numbers to more than " +
                                                 std::to_string(kMaxPadding) + " digits");
    return static_cast<int>(digits);
}

}  // namespace

FramePattern::FramePattern(const std::string& pattern) : text_(pattern) {
    if (pattern.empty()) throw Error(Status::InvalidArgument, "empty file pattern");
    // Only the file name part may hold the frame token; directories are taken literally.
    const size_t name_start = pattern.find_last_of('/') == std::string::npos ? 0 : pattern.find_last_of('/') + 1;
    for (size_t i = name_start; i < pattern.size(); ++i) {
        const char ch = pattern[i];
        size_t end = i;
        if (ch == '#' || ch == '@') {
            while (end < pattern.size() && pattern[end] == ch) ++end;
            const size_t run = end - i;
            padding_ = (ch == '#' && run == 1) ? 4 : checked_padding(pattern, run);
        } else if (ch == '%') {
            end = i + 1;
            std::string digits;
            while (end < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[end]))) digits += pattern[end++];
            if (end >= pattern.size() || pattern[end] != 'd') continue;
            ++end;
            // Leading zeros are the printf flag, not part of the width ("%040d" is 40 digits).
            const size_t first = std::min(digits.find_first_not_of('0'), digits.size());
            padding_ = first == digits.size()
                           ? 0
                           : checked_padding(pattern, digits.size() - first > 3 ? kMaxPadding + 1
                                                                               : std::stoul(digits.substr(first)));
        } else {
            continue;
        }
        prefix_ = pattern.substr(0, i);
        suffix_ = pattern.substr(end);
        has_token_ = true;
        break;
    }
    if (has_token_ && (suffix_.find('#') != std::string::npos || suffix_.find('@') != std::string::npos))
        throw Error(Status::InvalidArgument, "pattern '" + pattern + "' has more than one frame token");
}

std::string FramePattern::format(int64_t frame) const {
    if (!has_token_) return text_;
    // Sized for the padding (at most kMaxPadding) plus a sign and 19 digits: never truncated.
    char digits[kMaxPadding + 24];
    std::snprintf(digits, sizeof digits, "%0*lld", padding_, static_cast<long long>(frame));
    return prefix_ + digits + suffix_;
}

std::vector<int64_t> FramePattern::scan() const {
    if (!has_token_) {
        std::error_code ec;
        return fs::is_regular_file(text_, ec) ? std::vector<int64_t>{1} : std::vector<int64_t>{};
    }
    const size_t slash = prefix_.find_last_of('/');
    const fs::path dir = slash == std::string::npos ? fs::path(".") : fs::path(prefix_.substr(0, slash + 1));
    const std::string stem = slash == std::string::npos ? prefix_ : prefix_.substr(slash + 1);
    std::set<int64_t> frames;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        std::error_code type_ec;
        if (!it->is_regular_file(type_ec)) continue;  // e.g. a directory named like a frame
        if (name.size() <= stem.size() + suffix_.size()) continue;
        if (name.compare(0, stem.size(), stem) != 0) continue;
        if (name.compare(name.size() - suffix_.size(), suffix_.size(), suffix_) != 0) continue;
        const std::string middle = name.substr(stem.size(), name.size() - stem.size() - suffix_.size());
        size_t i = (middle[0] == '-') ? 1 : 0;
        if (i == middle.size()) continue;
        if (!std::all_of(middle.begin() + i, middle.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
            continue;
        // Padding zeros may be many; the number itself must fit in 18 digits.
        const size_t significant = middle.find_first_not_of('0', i);
        if (significant != std::string::npos && middle.size() - significant > 18) continue;
        const int64_t number = std::stoll(middle);
        if (format(number) == prefix_ + middle + suffix_) frames.insert(number);  // padding must match exactly
    }
    return {frames.begin(), frames.end()};
}

std::vector<int64_t> parse_frame_spec(const std::string& spec) {
    std::set<int64_t> frames;
    size_t pos = 0;
    auto bad = [&](const std::string& why) {
        return Error(Status::InvalidArgument, "invalid frame range '" + spec + "': " + why);
    };
    auto read_int = [&](int64_t& value) {
        size_t start = pos;
        if (pos < spec.size() && (spec[pos] == '-' || spec[pos] == '+')) ++pos;
        while (pos < spec.size() && std::isdigit(static_cast<unsigned char>(spec[pos]))) ++pos;
        if (pos == start || (pos == start + 1 && !std::isdigit(static_cast<unsigned char>(spec[start])))) throw bad("expected a number");
        if (pos - start > 18) throw bad("number too long");
        value = std::stoll(spec.substr(start, pos - start));
    };
    if (spec.empty()) throw bad("empty");
    while (pos < spec.size()) {
        int64_t first = 0, last = 0, step = 1;
        read_int(first);
        last = first;
        if (pos < spec.size() && spec[pos] == '-') {
            ++pos;
            read_int(last);
            if (pos < spec.size() && (spec[pos] == 'x' || spec[pos] == ':')) {
                ++pos;
                read_int(step);
                if (step < 1) throw bad("step must be >= 1");
            }
        }
        if (last < first) throw bad("range end before its start");
        if ((last - first) / step > 10000000) throw bad("more than 10 million frames");
        for (int64_t f = first; f <= last; f += step) frames.insert(f);
        if (pos < spec.size()) {
            if (spec[pos] != ',') throw bad(std::string("unexpected '") + spec[pos] + "'");
            ++pos;
            if (pos == spec.size()) throw bad("trailing comma");
        }
    }
    return {frames.begin(), frames.end()};
}

std::string format_frame_list(const std::vector<int64_t>& frames) {
    std::string out;
    for (size_t i = 0; i < frames.size();) {
        size_t j = i;
        while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
        if (!out.empty()) out += ",";
        out += std::to_string(frames[i]);
        if (j > i) out += "-" + std::to_string(frames[j]);
        i = j + 1;
    }
    return out;
}

}  // namespace statfilter
