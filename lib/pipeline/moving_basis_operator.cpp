#include "pipeline/moving_basis_operator.hpp"

#include <cblas.h>

#include <algorithm>
#include <cmath>

#include "statfilter/error.hpp"

namespace statfilter {

FrameWindow frame_window(int64_t centre, int64_t half_width, int64_t frames) {
    return {std::max<int64_t>(0, centre - half_width), std::min<int64_t>(frames - 1, centre + half_width)};
}

std::vector<double> window_weights(FrameWindow w, int64_t centre, double sigma, bool gaussian) {
    std::vector<double> weights(static_cast<size_t>(w.size()));
    double total = 0;
    for (int64_t j = w.first; j <= w.last; ++j) {
        const double d = static_cast<double>(j - centre);
        const double v = gaussian ? std::exp(-0.5 * d * d / (sigma * sigma)) : 1.0;
        weights[j - w.first] = v;
        total += v;
    }
    for (double& v : weights) v /= total;
    return weights;
}

std::vector<double> window_reconstruction(const std::vector<double>& shot_gram, int64_t frames, FrameWindow w,
                                          const std::vector<double>& weights, const RankRule& rank_rule, int64_t series,
                                          int64_t* chosen_rank) {
    const int64_t W = w.size();
    // Weighted centring: y_j = x_j - sum_l w_l x_l, so <y_i, y_j> = S_ij - (S w)_i - (S w)_j + w^T S w.
    auto S = [&](int64_t i, int64_t j) { return shot_gram[(w.first + i) * frames + (w.first + j)]; };
    std::vector<double> Sw(static_cast<size_t>(W), 0.0);
    double wSw = 0;
    for (int64_t i = 0; i < W; ++i)
        for (int64_t j = 0; j < W; ++j) Sw[i] += S(i, j) * weights[j];
    for (int64_t i = 0; i < W; ++i) wSw += weights[i] * Sw[i];
    std::vector<double> gram(static_cast<size_t>(W * W));  // the window's weighted, centred Gram
    for (int64_t i = 0; i < W; ++i)
        for (int64_t j = 0; j < W; ++j)
            gram[i * W + j] = std::sqrt(weights[i] * weights[j]) * (S(i, j) - Sw[i] - Sw[j] + wSw);
    std::vector<double> eigenvalues;
    symmetric_eigen(W, gram, eigenvalues);
    const int64_t k = rank_rule(eigenvalues, series, W);
    if (chosen_rank) *chosen_rank = k;
    // D = Q^-1 U_k U_k^T Q (I - 1 w^T) + 1 w^T with Q = diag(sqrt(w)): window frames -> reconstruction.
    std::vector<double> P(static_cast<size_t>(W * W), 0.0);  // U_k U_k^T
    for (int64_t i = 0; i < W; ++i)
        for (int64_t j = 0; j < W; ++j)
            for (int64_t c = 0; c < k; ++c) P[i * W + j] += gram[i * W + c] * gram[j * W + c];
    std::vector<double> D(static_cast<size_t>(W * W));
    for (int64_t i = 0; i < W; ++i) {
        double row_sum = 0;  // sum_j of Q^-1 P Q, used for the - (...) 1 w^T part
        for (int64_t j = 0; j < W; ++j) {
            D[i * W + j] = P[i * W + j] * std::sqrt(weights[j]) / std::sqrt(weights[i]);
            row_sum += D[i * W + j];
        }
        for (int64_t j = 0; j < W; ++j) D[i * W + j] += weights[j] * (1.0 - row_sum);
    }
    return D;
}

WindowWeights parse_window_weights(const std::string& name) {
    if (name == "reconstruction") return WindowWeights::Reconstruction;
    if (name == "basis") return WindowWeights::Basis;
    if (name == "uniform") return WindowWeights::Uniform;
    throw Error(Status::InvalidArgument, "weights must be reconstruction, basis or uniform, not '" + name + "'");
}

MovingOperator moving_basis_operator(const std::vector<double>& gram, int64_t F, int64_t series, const MovingWindow& mw,
                                     const RankRule& rank_rule) {
    std::vector<double> S(gram);  // window_reconstruction reads both triangles
    for (int64_t i = 0; i < F; ++i)
        for (int64_t j = 0; j < i; ++j) S[i * F + j] = S[j * F + i];
    const int64_t h = mw.half_width;
    const bool blend_windows = mw.weights == WindowWeights::Reconstruction;
    MovingOperator op;
    op.reach = mw.reach();
    op.M.assign(static_cast<size_t>(F * F), 0.0);
    std::vector<double> blend(static_cast<size_t>(F), 0.0);
    for (int64_t s = 0; s < F; ++s) {
        const FrameWindow w = frame_window(s, h, F);
        int64_t k = 0;
        const auto D = window_reconstruction(S, F, w, window_weights(w, s, mw.sigma, mw.weights == WindowWeights::Basis),
                                             rank_rule, series, &k);
        op.rank_sum += static_cast<double>(k);
        ++op.windows;
        if (!blend_windows) {  // frame s from its own window only
            for (int64_t j = 0; j < w.size(); ++j) op.M[s * F + w.first + j] = D[(s - w.first) * w.size() + j];
            continue;
        }
        for (int64_t t = w.first; t <= w.last; ++t) {  // every frame of the window, Gaussian-weighted
            const double d = static_cast<double>(t - s), b = std::exp(-0.5 * d * d / (mw.sigma * mw.sigma));
            blend[t] += b;
            for (int64_t j = 0; j < w.size(); ++j) op.M[t * F + w.first + j] += b * D[(t - w.first) * w.size() + j];
        }
    }
    if (blend_windows)
        for (int64_t t = 0; t < F; ++t)
            for (int64_t j = 0; j < F; ++j) op.M[t * F + j] /= blend[t];
    return op;
}

void apply_moving_operator(const MovingOperator& op, int64_t F, int64_t n, std::vector<double>& tile,
                           std::vector<double>& scratch) {
    scratch.assign(static_cast<size_t>(F * n), 0.0);
    for (int64_t i = 0; i < F; ++i)
        for (int64_t j = std::max<int64_t>(0, i - op.reach); j <= std::min(F - 1, i + op.reach); ++j)
            if (op.M[i * F + j] != 0.0)
                cblas_daxpy(static_cast<int>(n), op.M[i * F + j], &tile[j * n], 1, &scratch[i * n], 1);
    tile.swap(scratch);
}

}  // namespace statfilter
