// Moving basis: each frame is denoised by a PCA of the frames around it, so the basis follows
// slow change instead of averaging the whole sequence into one. Every window's reconstruction is a
// linear combination of the window's frames, so the whole filter is one banded F x F operator M
// applied to every time series: out = M x. M is built from a band of frame inner products computed
// once (lags up to the window size), from which every window's weighted, centred Gram follows in
// O(window^2): no per-frame pass over the pixels, and no full Gram per window.
#include <cblas.h>

#include <cmath>

#include "filters/builtin_filters.hpp"
#include "filters/moving_basis.hpp"
#include "filters/temporal_params.hpp"
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

std::vector<double> window_reconstruction(const std::vector<double>& band, int64_t frames, FrameWindow w,
                                          const std::vector<double>& weights, const RankRule& rank_rule, int64_t series,
                                          int64_t* chosen_rank) {
    const int64_t W = w.size();
    // Weighted centring: y_j = x_j - sum_l w_l x_l, so <y_i, y_j> = S_ij - (S w)_i - (S w)_j + w^T S w.
    auto S = [&](int64_t i, int64_t j) { return band[(w.first + i) * frames + (w.first + j)]; };
    std::vector<double> Sw(static_cast<size_t>(W), 0.0);
    double wSw = 0;
    for (int64_t i = 0; i < W; ++i)
        for (int64_t j = 0; j < W; ++j) Sw[i] += S(i, j) * weights[j];
    for (int64_t i = 0; i < W; ++i) wSw += weights[i] * Sw[i];
    std::vector<double> gram(static_cast<size_t>(W * W));
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

namespace {

// Inner products <x_i, x_j> of centred series for |i - j| <= lag, accumulated over tiles (F x F, banded).
std::vector<double> frame_inner_product_band(PreparedSeries& prepared, int64_t lag, int64_t* series,
                                             const ProgressSpan& progress) {
    const int64_t F = prepared.frames();
    std::vector<double> band(static_cast<size_t>(F * F), 0.0);
    *series = 0;
    prepared.read(progress, [&](const PreparedTile& t) {
        for (int64_t i = 0; i < F; ++i)
            for (int64_t j = i; j <= std::min(F - 1, i + lag); ++j)
                band[i * F + j] += cblas_ddot(static_cast<int>(t.n), &t.tile[i * t.n], 1, &t.tile[j * t.n], 1);
        *series += t.n;
    });
    for (int64_t i = 0; i < F; ++i)
        for (int64_t j = 0; j < i; ++j) band[i * F + j] = band[j * F + i];
    return band;
}

// out = M x for every series, M banded with half-bandwidth `lag`.
void apply_temporal_operator(PreparedSeries& prepared, Sequence& output, const std::vector<double>& M, int64_t lag,
                             const ProgressSpan& progress) {
    const int64_t F = prepared.frames();
    std::vector<double> result;
    prepared.consume(progress, [&](PreparedTile& t) {
        const int64_t n = t.n;
        result.assign(static_cast<size_t>(F * n), 0.0);
        for (int64_t i = 0; i < F; ++i)
            for (int64_t j = std::max<int64_t>(0, i - lag); j <= std::min(F - 1, i + lag); ++j)
                if (M[i * F + j] != 0.0)
                    cblas_daxpy(static_cast<int>(n), M[i * F + j], &t.tile[j * n], 1, &result[i * n], 1);
        t.tile.swap(result);  // M keeps constants (M 1 = 1), so the means add back as usual
        prepared.finish(t, output);
    });
}

class MovingBasisFilter final : public Filter {
public:
    MovingBasisFilter() : Filter(make_params()) {}

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {
            rank_param("auto"),
            energy_param(),
            int_param("half_width", "8", 1, 10000, "window of frames t-h..t+h around each frame (one-sided at the ends)"),
            float_param("sigma", "4", 1e-3, 1e6, "Gaussian sigma of the window weights, in frames"),
            choice_param("weights", "reconstruction", {"reconstruction", "basis", "uniform"},
                         "where the Gaussian goes: blend overlapping uniform-window reconstructions (reconstruction), "
                         "weight the window's PCA (basis, the study), or nowhere (uniform)"),
        };
        for (auto& c : temporal_common_params()) p.push_back(c);
        return p;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        const TemporalSetup setup = temporal_setup(params(), input);
        const Shape& shape = input.shape();
        const int64_t F = shape.frames, h = params().get_int("half_width");
        const double sigma = params().get_float("sigma");
        const std::string mode = params().get_string("weights");
        const ParamSet& ps = params();
        const RankRule rule = [&ps](const std::vector<double>& ev, int64_t series, int64_t frames) {
            return choose_rank(ps, ev, series, frames).rank;
        };
        const auto groups = basis_groups(shape, setup.shared_basis);
        double rank_sum = 0;
        int64_t windows = 0;
        for (size_t g = 0; g < groups.size(); ++g) {
            const double share = 1.0 / groups.size(), at = g * share;
            PreparedSeries prepared(input, groups[g], setup.prep, setup.budget_bytes, 3);
            // "reconstruction" blends windows centred up to h away, so its operator reaches 2h.
            const int64_t lag = mode == "reconstruction" ? 2 * h : h;
            int64_t series = 0;
            const auto band = frame_inner_product_band(prepared, 2 * h, &series,
                                                       {progress, at, 0.4 * share, "band"});
            std::vector<double> M(static_cast<size_t>(F * F), 0.0), blend(static_cast<size_t>(F), 0.0);
            for (int64_t s = 0; s < F; ++s) {
                const FrameWindow w = frame_window(s, h, F);
                int64_t k = 0;
                const auto D = window_reconstruction(band, F, w, window_weights(w, s, sigma, mode == "basis"), rule,
                                                     series, &k);
                rank_sum += static_cast<double>(k);
                ++windows;
                if (mode != "reconstruction") {  // frame s from its own window only
                    for (int64_t j = 0; j < w.size(); ++j) M[s * F + w.first + j] = D[(s - w.first) * w.size() + j];
                    continue;
                }
                for (int64_t t = w.first; t <= w.last; ++t) {  // every frame of the window, Gaussian-weighted
                    const double d = static_cast<double>(t - s), b = std::exp(-0.5 * d * d / (sigma * sigma));
                    blend[t] += b;
                    for (int64_t j = 0; j < w.size(); ++j) M[t * F + w.first + j] += b * D[(t - w.first) * w.size() + j];
                }
            }
            if (mode == "reconstruction")
                for (int64_t t = 0; t < F; ++t)
                    for (int64_t j = 0; j < F; ++j) M[t * F + j] /= blend[t];
            apply_temporal_operator(prepared, output, M, lag,
                                    {progress, at + 0.4 * share, 0.6 * share, "reconstruct"});
        }
        mutable_results().set("mean_rank", rank_sum / static_cast<double>(windows));
        mutable_results().set("nonfinite_repaired", static_cast<double>(setup.nonfinite_samples));
    }
};

}  // namespace

std::unique_ptr<Filter> make_moving_basis_filter() { return std::make_unique<MovingBasisFilter>(); }

}  // namespace statfilter
