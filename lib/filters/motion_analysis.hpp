// The motion maps as the motion and hybrid filters compute them from their parameters.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "statfilter/filter.hpp"
#include "statfilter/motion.hpp"

namespace statfilter {

std::vector<ParamSpec> motion_params();

struct MotionMaps {
    std::shared_ptr<Sequence> alpha;  // 1 frame, 1 channel; 1 = stationary
    std::shared_ptr<Sequence> beta;   // F frames, 1 channel; 1 = moving now
    std::string beta_source;          // "zscore" or "aux"
};

// Uses the temporal parameters (transform, nonfinite, shared_basis, memory_mb) and motion_params().
MotionMaps compute_motion(const Sequence& input, const ParamSet& params, const ProgressSpan& progress);

// alpha alone (no beta), e.g. to decide whether anything moves at all.
std::shared_ptr<Sequence> compute_alpha(const Sequence& input, const ParamSet& params, const ProgressSpan& progress);

// The two stages, for a caller that already has the series and their basis (the hybrid).
std::shared_ptr<Sequence> compute_alpha(PreparedSeries& series, const TemporalBasis& basis, const ParamSet& params,
                                        const ProgressSpan& progress);
void compute_beta(const Sequence& input, const ParamSet& params, MotionMaps& maps);

// The share of each pixel that moves, 1-frame, 1-channel: 1 - alpha, raised to 1 where the temporal-
// change test (change_z > 0), the albedo/normal passes (beta from them, in any frame) or the
// renderer's motion vectors (when given) say the pixel moves. The
// still/moving decisions of the hybrid and of auto and the hybrid's motion-compensated region use it.
std::shared_ptr<Sequence> moving_weight(const Sequence& input, const Sequence& alpha, const Sequence* vectors,
                                        const ParamSet& params);

// A renderer pass (albedo, normal) for the input's frames, read from a file pattern; its frames and
// size must match the input's.
std::unique_ptr<Sequence> read_pass(const Sequence& input, const std::string& pattern);

}  // namespace statfilter
