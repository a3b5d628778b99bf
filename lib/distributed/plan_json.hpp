// The small JSON pieces a plan writer spells out (lib/distributed/tile_plan.cpp, detect_plan.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace statfilter {

// The plan format's versions. 1: the first. 2: the front end names inputs as files ("inputs"), which
// a reader of version 1 would pass over, running the filter without the renderer's passes. A plan is
// written with the least version its content needs, so older workers still take the plans they run
// right, and a reader refuses a version newer than kPlanVersionRead instead of guessing.
constexpr int kPlanVersionFirst = 1;
constexpr int kPlanVersionInputs = 2;
constexpr int kPlanVersionRead = kPlanVersionInputs;

inline std::string range_json(int64_t a, int64_t b) { return "[" + std::to_string(a) + ", " + std::to_string(b) + "]"; }

inline std::string list_json(const std::vector<int64_t>& v) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    return s + "]";
}

}  // namespace statfilter
