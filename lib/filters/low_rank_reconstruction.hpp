// Projection onto the leading temporal components and reconstruction from them, tile by tile.
#pragma once
#include <vector>

#include "statfilter/temporal_basis.hpp"

namespace statfilter {

// coefficients (rank x n) = V_rank^T tile (F x n).
void project_onto_basis(const TemporalBasis& basis, int64_t rank, const double* tile, int64_t n, double* coefficients);

// Writes mu + V_k V_k^T (x - mu) for every series of the group. With pixel_ranks, pixel p keeps only
// its first pixel_ranks[p] (<= rank) components.
// The last pass over the series.
void reconstruct_low_rank(PreparedSeries& series, Sequence& output, const TemporalBasis& basis, int64_t rank,
                          const std::vector<int64_t>* pixel_ranks, const ProgressSpan& progress);

}  // namespace statfilter
