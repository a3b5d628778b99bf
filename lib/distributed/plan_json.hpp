// The small JSON pieces a plan writer spells out (lib/distributed/tile_plan.cpp, detect_plan.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace statfilter {

// The plan format's versions. 1: the first. 2: the renderer's passes named (front end "inputs", the
// albedo/normal parameters; files, a multilayer file's layer, or a layer's name), which a reader
// from before them would pass over or read whole. A plan is written with the least version its
// content needs, and a reader refuses a version newer than kPlanVersionRead instead of guessing.
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
