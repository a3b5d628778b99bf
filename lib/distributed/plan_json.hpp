// The small JSON pieces a plan writer spells out (lib/distributed/tile_plan.cpp, detect_plan.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace statfilter {

inline std::string range_json(int64_t a, int64_t b) { return "[" + std::to_string(a) + ", " + std::to_string(b) + "]"; }

inline std::string list_json(const std::vector<int64_t>& v) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    return s + "]";
}

}  // namespace statfilter
