// The pieces of the moving-basis filter that tests check against a plain per-window PCA.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "statfilter/temporal_basis.hpp"

namespace statfilter {

struct FrameWindow {
    int64_t first = 0, last = 0;  // inclusive
    int64_t size() const { return last - first + 1; }
};

// Frames centre-h .. centre+h, cut at the sequence ends (one-sided there).
FrameWindow frame_window(int64_t centre, int64_t half_width, int64_t frames);

// Normalised weights over the window: Gaussian around centre, or uniform.
std::vector<double> window_weights(FrameWindow window, int64_t centre, double sigma, bool gaussian);

// Picks a rank from a window's eigenvalues (descending), given the series count and window size.
using RankRule = std::function<int64_t(const std::vector<double>& eigenvalues, int64_t series, int64_t frames)>;

// The W x W matrix D that maps a window's frames to their weighted rank-k PCA reconstruction,
// derived from band (F x F inner products of centred series, valid within the window).
std::vector<double> window_reconstruction(const std::vector<double>& band, int64_t frames, FrameWindow window,
                                          const std::vector<double>& weights, const RankRule& rank_rule,
                                          int64_t series, int64_t* chosen_rank);

}  // namespace statfilter
