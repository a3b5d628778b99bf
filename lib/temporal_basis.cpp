#include "statfilter/temporal_basis.hpp"

#include <cblas.h>
#include <lapacke.h>

#include <algorithm>
#include <cmath>

#include "statfilter/error.hpp"

namespace statfilter {

void symmetric_eigen(int64_t n, std::vector<double>& a, std::vector<double>& w) {
    w.assign(static_cast<size_t>(n), 0.0);
    const lapack_int info =
        LAPACKE_dsyevd(LAPACK_ROW_MAJOR, 'V', 'U', static_cast<lapack_int>(n), a.data(), static_cast<lapack_int>(n), w.data());
    if (info != 0) throw Error(Status::Numeric, "eigendecomposition failed (LAPACK dsyevd info " + std::to_string(info) + ")");
    // LAPACK returns ascending order: reverse columns and values.
    std::reverse(w.begin(), w.end());
    for (int64_t r = 0; r < n; ++r) std::reverse(a.begin() + r * n, a.begin() + (r + 1) * n);
    for (double& v : w) v = std::max(v, 0.0);  // rounding can leave tiny negatives
}

void accumulate_gram(const PreparedTile& t, int64_t F, std::vector<double>& gram) {
    // Float inputs squared in double cannot overflow (3.4e38^2 ~ 1e77), so no rescaling is needed.
    cblas_dsyrk(CblasRowMajor, CblasUpper, CblasNoTrans, static_cast<int>(F), static_cast<int>(t.n), 1.0, t.tile.data(),
                static_cast<int>(t.n), 1.0, gram.data(), static_cast<int>(F));
}

TemporalBasis basis_from_gram(std::vector<double> gram, int64_t F, int64_t series) {
    TemporalBasis basis;
    basis.frames = F;
    basis.series = series;
    for (int64_t i = 0; i < F; ++i)
        for (int64_t j = 0; j < i; ++j) gram[i * F + j] = gram[j * F + i];
    for (double v : gram)
        if (!std::isfinite(v))
            throw Error(Status::Numeric, "the temporal Gram matrix is not finite (NaN/Inf in the input?)");
    symmetric_eigen(F, gram, basis.eigenvalues);
    basis.vectors = std::move(gram);
    return basis;
}

TemporalBasis compute_temporal_basis(PreparedSeries& series, const ProgressSpan& progress) {
    const int64_t F = series.frames();
    std::vector<double> gram(static_cast<size_t>(F * F), 0.0);
    int64_t count = 0;
    series.read(progress, [&](const PreparedTile& t) {
        accumulate_gram(t, F, gram);
        count += t.n;
    });
    return basis_from_gram(std::move(gram), F, count);
}

int64_t max_useful_rank(int64_t series, int64_t frames) { return std::max<int64_t>(0, std::min(series, frames - 1)); }

namespace {

// The median of the Marchenko-Pastur distribution with aspect ratio beta, by bisection on its CDF
// (numerical integration of the density); used to turn the median singular value into sigma.
double marchenko_pastur_median(double beta) {
    const double lo = (1 - std::sqrt(beta)) * (1 - std::sqrt(beta)), hi = (1 + std::sqrt(beta)) * (1 + std::sqrt(beta));
    auto density = [&](double x) {
        const double v = (hi - x) * (x - lo);
        return v > 0 ? std::sqrt(v) / (2 * M_PI * beta * x) : 0.0;
    };
    auto cdf = [&](double x) {
        const int steps = 2000;
        double sum = 0, h = (x - lo) / steps;
        for (int i = 0; i < steps; ++i) sum += density(lo + (i + 0.5) * h);
        return sum * h;
    };
    double a = lo, b = hi;
    for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (a + b);
        (cdf(mid) < 0.5 ? a : b) = mid;
    }
    return 0.5 * (a + b);
}

}  // namespace

RankChoice gavish_donoho_rank(const std::vector<double>& eigenvalues, int64_t series, int64_t frames) {
    RankChoice choice;
    // Centring removes one degree of freedom per series: the data has frames - 1 useful columns.
    const int64_t m = max_useful_rank(series, frames);
    if (m <= 0) return choice;
    const int64_t cols = frames - 1;
    const double beta = static_cast<double>(std::min(series, cols)) / static_cast<double>(std::max(series, cols));
    std::vector<double> s;
    for (int64_t i = 0; i < m; ++i) s.push_back(std::sqrt(eigenvalues[static_cast<size_t>(i)]));
    std::vector<double> sorted = s;
    std::nth_element(sorted.begin(), sorted.begin() + m / 2, sorted.end());
    double median = sorted[static_cast<size_t>(m / 2)];
    if (m % 2 == 0) {
        const double below = *std::max_element(sorted.begin(), sorted.begin() + m / 2);
        median = 0.5 * (median + below);
    }
    const double omega = 0.56 * beta * beta * beta - 0.95 * beta * beta + 1.82 * beta + 1.43;
    const double tau = omega * median;
    for (double v : s) choice.rank += v > tau ? 1 : 0;
    const double n_big = static_cast<double>(std::max(series, cols));
    choice.noise_sigma = median / std::sqrt(n_big * marchenko_pastur_median(beta));
    return choice;
}

int64_t energy_rank(const std::vector<double>& eigenvalues, double fraction) {
    double total = 0;
    for (double v : eigenvalues) total += v;
    if (total <= 0) return 0;
    double kept = 0;
    for (size_t k = 0; k < eigenvalues.size(); ++k) {
        if (kept >= fraction * total) return static_cast<int64_t>(k);
        kept += eigenvalues[k];
    }
    return static_cast<int64_t>(eigenvalues.size());
}

}  // namespace statfilter
