// The detection's degree map for people: one RGB frame, degree 0 dark blue through yellow at the
// highest degree, pixels that no degree explains in red. Written by `statfilter detect --preview`
// and by a detect plan's masks task, so the two are the same image.
#pragma once
#include <cstdint>
#include <memory>

#include "statfilter/sequence.hpp"

namespace statfilter {

// degree_map: one frame, one channel (the detect filter's "degree_map" result: degree + 1 where no
// degree explains the pixel); degree: the filter's highest degree. Returns 1 x H x W x 3 (R, G, B).
std::unique_ptr<Sequence> degree_preview(const Sequence& degree_map, int64_t degree);

}  // namespace statfilter
