// The moving basis as one temporal operator: each frame is denoised by a PCA of the frames around
// it, so the basis follows slow change instead of averaging the whole shot into one. Every window's
// reconstruction is a linear combination of the window's frames, so the whole filter is one banded
// F x F operator M applied to every centred time series, out = M x. M follows from the shot's Gram
// (the same F x F sums the global PCA's statistics pass makes): every window's weighted, centred
// Gram is a W x W block of it, corrected in O(W^2). So the moving basis streams, and cuts into tile
// tasks, exactly as the global PCA does.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
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
// derived from shot_gram (F x F inner products of centred series, symmetric, valid within the window).
std::vector<double> window_reconstruction(const std::vector<double>& shot_gram, int64_t frames, FrameWindow window,
                                          const std::vector<double>& weights, const RankRule& rank_rule,
                                          int64_t series, int64_t* chosen_rank);

// Where the Gaussian goes: blend overlapping uniform-window reconstructions, weight each window's
// PCA (the study), or nowhere.
enum class WindowWeights { Reconstruction, Basis, Uniform };
WindowWeights parse_window_weights(const std::string& name);

struct MovingWindow {
    int64_t half_width = 0;  // 0: no moving basis (one global basis)
    double sigma = 4;        // of the Gaussian, in frames
    WindowWeights weights = WindowWeights::Reconstruction;
    // Frames either side the operator reaches: blending windows centred up to h away reaches 2h.
    int64_t reach() const { return weights == WindowWeights::Reconstruction ? 2 * half_width : half_width; }
};

struct MovingOperator {
    std::vector<double> M;  // F x F, row t: frame t's output from the frames t - reach .. t + reach
    int64_t reach = 0;
    double rank_sum = 0;    // the ranks the windows chose, summed
    int64_t windows = 0;
};

// M from the shot's Gram (F x F, the upper triangle is read) over `series` centred series.
MovingOperator moving_basis_operator(const std::vector<double>& gram, int64_t frames, int64_t series,
                                     const MovingWindow& window, const RankRule& rank_rule);

// out = M x on the n series of tile (frame-major, F rows of n), through scratch (resized as needed);
// M keeps constants (M 1 = 1), so a series' mean added back after is the mean it had.
void apply_moving_operator(const MovingOperator& op, int64_t frames, int64_t n, std::vector<double>& tile,
                           std::vector<double>& scratch);

}  // namespace statfilter
