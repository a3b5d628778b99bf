#include "filters/low_rank_reconstruction.hpp"

#include <cblas.h>

#include <algorithm>

namespace statfilter {

void project_onto_basis(const TemporalBasis& basis, int64_t rank, const double* tile, int64_t n, double* coefficients) {
    const int F = static_cast<int>(basis.frames);
    cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, static_cast<int>(rank), static_cast<int>(n), F, 1.0,
                basis.vectors.data(), F, tile, static_cast<int>(n), 0.0, coefficients, static_cast<int>(n));
}

void reconstruct_low_rank(const Sequence& input, Sequence& output, ChannelSelection group,
                          const std::vector<PixelRange>& tiles, const SeriesPrep& prep, const TemporalBasis& basis,
                          int64_t rank, const std::vector<int64_t>* pixel_ranks, const ProgressSpan& progress) {
    const int64_t F = basis.frames;
    std::vector<double> tile, means, a;
    for (size_t t = 0; t < tiles.size(); ++t) {
        progress.report(static_cast<double>(t) / tiles.size());
        const int64_t n = tiles[t].size() * group.count;
        tile.resize(static_cast<size_t>(F * n));
        means.resize(static_cast<size_t>(n));
        gather_tile(input, tiles[t], group, tile.data());
        prepare_tile(tile.data(), F, n, prep, means.data());
        if (rank > 0) {
            // Two thin products, A = V_k^T X then X = V_k A, instead of one F x F operator.
            a.resize(static_cast<size_t>(rank * n));
            project_onto_basis(basis, rank, tile.data(), n, a.data());
            if (pixel_ranks)
                for (int64_t j = 0; j < n; ++j)
                    for (int64_t i = (*pixel_ranks)[tiles[t].begin + j / group.count]; i < rank; ++i) a[i * n + j] = 0;
            cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(F), static_cast<int>(n),
                        static_cast<int>(rank), 1.0, basis.vectors.data(), static_cast<int>(F), a.data(),
                        static_cast<int>(n), 0.0, tile.data(), static_cast<int>(n));
        } else {
            std::fill(tile.begin(), tile.end(), 0.0);
        }
        for (int64_t f = 0; f < F; ++f)
            for (int64_t j = 0; j < n; ++j) tile[f * n + j] += means[j];
        inverse_transform(prep.transform, tile.data(), tile.size());
        scatter_tile(tile.data(), tiles[t], group, output);
    }
    progress.report(1.0);
}

}  // namespace statfilter
