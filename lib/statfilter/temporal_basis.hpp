// The temporal basis of a sequence: eigenvectors of the F x F Gram matrix of its centred time series,
// accumulated in double over pixel tiles (identical for any tile size up to summation order).
#pragma once
#include <cstdint>
#include <vector>

#include "statfilter/prepared_series.hpp"

namespace statfilter {

struct TemporalBasis {
    int64_t frames = 0;
    int64_t series = 0;                // rows of the data matrix (pixels x channels sharing the basis)
    std::vector<double> eigenvalues;   // descending, >= 0 (squared singular values)
    std::vector<double> vectors;       // F x F row-major: column k is the k-th temporal component
    double vector(int64_t frame, int64_t k) const { return vectors[frame * frames + k]; }
};

// Accumulates the Gram matrix over the tiles and eigendecomposes it (LAPACK dsyevd).
TemporalBasis compute_temporal_basis(PreparedSeries& series, const ProgressSpan& progress);
// The same in pieces, for passes that see the tiles band by band: gram (F x F, upper triangle) +=
// the tile's centred series' inner products; then the basis of the summed Gram of `series` series.
void accumulate_gram(const PreparedTile& tile, int64_t frames, std::vector<double>& gram);
TemporalBasis basis_from_gram(std::vector<double> gram, int64_t frames, int64_t series);

// Eigendecomposition of a symmetric F x F matrix (row-major, upper triangle used): descending.
void symmetric_eigen(int64_t n, std::vector<double>& matrix, std::vector<double>& eigenvalues);

// Rank choices on the eigenvalues of centred data with `series` rows and `frames` columns.
struct RankChoice {
    int64_t rank = 0;
    double noise_sigma = 0;  // estimated noise standard deviation per sample (auto only)
};
// Gavish & Donoho (2014), unknown noise: keep singular values above omega(beta) * median.
RankChoice gavish_donoho_rank(const std::vector<double>& eigenvalues, int64_t series, int64_t frames);
// Smallest rank whose components hold at least `fraction` of the variance.
int64_t energy_rank(const std::vector<double>& eigenvalues, double fraction);
// The most components that carry any variance: min(series, frames - 1).
int64_t max_useful_rank(int64_t series, int64_t frames);

}  // namespace statfilter
