// Minimal JSON output for --json reports.
//
// The library writes its JSON (crops.json) with statfilter::json_quote and json_number in
// lib/json.cpp; the CLI uses only the public C header, so it cannot call them: these two are the
// same code and must stay so (same escapes, same number format), tests/cli checks both outputs.
#pragma once
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <statfilter/statfilter.h>

namespace statfilter_cli {

inline std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\t': out += "\\t"; break;
        case '\r': out += "\\r"; break;
        default:
            if (c < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", c);
                out += buf;
            } else {
                out += static_cast<char>(c);
            }
        }
    }
    return out + "\"";
}

// The shortest of 15, 16 or 17 significant digits that reads back as the same double (0.1, not
// 0.10000000000000001). JSON has no NaN/Inf: those become null.
inline std::string json_number(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[64];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

// A text that is a whole JSON number ("3", "-0.25", "1e-3"), as some results are kept as text.
inline bool is_json_number_text(const std::string& s) {
    size_t i = 0;
    const auto digits = [&] {
        const size_t start = i;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
        return i > start;
    };
    if (i < s.size() && s[i] == '-') ++i;
    if (!digits()) return false;
    if (i < s.size() && s[i] == '.' && (++i, !digits())) return false;
    if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
        if (!digits()) return false;
    }
    return i == s.size();
}

// A filter result as JSON: a number when the library has it as one (sf_filter_result_float) or its
// text is a number, else the text as a string.
inline std::string json_filter_result(sf_filter filter, const char* name) {
    double number = 0;
    if (sf_filter_result_float(filter, name, &number) == SF_OK) return json_number(number);
    const char* text = nullptr;
    if (sf_filter_result_string(filter, name, &text) != SF_OK || !text) return "null";
    return is_json_number_text(text) ? json_number(std::strtod(text, nullptr)) : json_string(text);
}

}  // namespace statfilter_cli
