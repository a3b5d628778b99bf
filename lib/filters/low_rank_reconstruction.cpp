#include "filters/low_rank_reconstruction.hpp"

#include <cblas.h>

#include <algorithm>

namespace statfilter {

void project_onto_basis(const TemporalBasis& basis, int64_t rank, const double* tile, int64_t n, double* coefficients) {
    const int F = static_cast<int>(basis.frames);
    cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, static_cast<int>(rank), static_cast<int>(n), F, 1.0,
                basis.vectors.data(), F, tile, static_cast<int>(n), 0.0, coefficients, static_cast<int>(n));
}

void reconstruct_low_rank(PreparedSeries& series, Sequence& output, const TemporalBasis& basis, int64_t rank,
                          const std::vector<int64_t>* pixel_ranks, const ProgressSpan& progress) {
    const int64_t F = basis.frames;
    const int64_t channels = series.group().count;
    std::vector<double> a;
    series.consume(progress, [&](PreparedTile& t) {
        const int64_t n = t.n;
        if (rank > 0) {
            // Two thin products, A = V_k^T X then X = V_k A, instead of one F x F operator.
            a.resize(static_cast<size_t>(rank * n));
            project_onto_basis(basis, rank, t.tile.data(), n, a.data());
            if (pixel_ranks)
                for (int64_t j = 0; j < n; ++j)
                    for (int64_t i = (*pixel_ranks)[t.range.begin + j / channels]; i < rank; ++i) a[i * n + j] = 0;
            cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(F), static_cast<int>(n),
                        static_cast<int>(rank), 1.0, basis.vectors.data(), static_cast<int>(F), a.data(),
                        static_cast<int>(n), 0.0, t.tile.data(), static_cast<int>(n));
        } else {
            std::fill(t.tile.begin(), t.tile.end(), 0.0);
        }
        series.finish(t, output);
    });
}

}  // namespace statfilter
