// The temporal basis of a sequence: eigenvectors of the F x F Gram matrix of its centred time series,
// accumulated in double over pixel tiles (identical for any tile size up to summation order).
#pragma once
#include <cstdint>
#include <vector>

#include "statfilter/nonfinite.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/time_series_tiles.hpp"
#include "statfilter/value_transform.hpp"

namespace statfilter {

// How a gathered tile becomes the centred series the basis describes.
struct SeriesPrep {
    ValueTransform transform = ValueTransform::None;
    bool repair_nonfinite = false;
};

// Repairs and transforms a gathered F x n tile, then centres every series; its means go to means[n].
void prepare_tile(double* tile, int64_t frames, int64_t n, const SeriesPrep& prep, double* means);

// One gathered, prepared tile: tile[f * n + j] is series j in frame f, centred; means[j] its mean.
struct PreparedTile {
    PixelRange range;
    int64_t n = 0;
    std::vector<double> tile, means;
};

// Gathers and prepares each tile in turn, hands it to visit(PreparedTile&), and reports progress.
template <class Visit>
void for_each_prepared_tile(const Sequence& seq, ChannelSelection channels, const std::vector<PixelRange>& tiles,
                            const SeriesPrep& prep, const ProgressSpan& progress, Visit&& visit) {
    const int64_t F = seq.shape().frames;
    PreparedTile t;
    for (size_t i = 0; i < tiles.size(); ++i) {
        progress.report(static_cast<double>(i) / tiles.size());
        t.range = tiles[i];
        t.n = tiles[i].size() * channels.count;
        t.tile.resize(static_cast<size_t>(F * t.n));
        t.means.resize(static_cast<size_t>(t.n));
        gather_tile(seq, t.range, channels, t.tile.data());
        prepare_tile(t.tile.data(), F, t.n, prep, t.means.data());
        visit(t);
    }
    progress.report(1.0);
}

// Adds the means back, undoes the transform and writes the tile's series to the output.
void finish_tile(PreparedTile& t, int64_t frames, ChannelSelection channels, const SeriesPrep& prep, Sequence& output);

struct TemporalBasis {
    int64_t frames = 0;
    int64_t series = 0;                // rows of the data matrix (pixels x channels sharing the basis)
    std::vector<double> eigenvalues;   // descending, >= 0 (squared singular values)
    std::vector<double> vectors;       // F x F row-major: column k is the k-th temporal component
    double vector(int64_t frame, int64_t k) const { return vectors[frame * frames + k]; }
};

// Accumulates the Gram matrix over the tiles and eigendecomposes it (LAPACK dsyevd).
TemporalBasis compute_temporal_basis(const Sequence& seq, ChannelSelection channels,
                                     const std::vector<PixelRange>& tiles, const SeriesPrep& prep,
                                     const ProgressSpan& progress);

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
