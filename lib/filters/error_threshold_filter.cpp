// The study's error threshold method: each pixel keeps its own number of temporal components.
// With an orthonormal basis, adding component i lowers a series' squared reconstruction error by
// exactly a_i^2 (its coefficient squared), so the Delta(error) test needs no reconstructions. One
// pixel's coefficients at low sample counts are mostly noise, so the test pools a_i^2 over a small
// window and compares it with the local noise level, estimated from the components beyond max_rank.
#include <opencv2/imgproc.hpp>

#include "filters/builtin_filters.hpp"
#include "filters/low_rank_reconstruction.hpp"
#include "filters/temporal_params.hpp"
#include "statfilter/error.hpp"

namespace statfilter {
namespace {

// Per-pixel coefficient energies, summed over the group's channels: planes[i][p] for component i,
// and the energy beyond the kept components in tail[p].
struct CoefficientEnergy {
    std::vector<cv::Mat> planes;
    cv::Mat tail;
};

CoefficientEnergy coefficient_energy(PreparedSeries& series, const Shape& s, const TemporalBasis& basis, int64_t rank,
                                     const ProgressSpan& progress) {
    const int64_t F = s.frames;
    CoefficientEnergy e;
    for (int64_t i = 0; i < rank; ++i) e.planes.emplace_back(static_cast<int>(s.height), static_cast<int>(s.width), CV_64F, cv::Scalar(0));
    e.tail = cv::Mat(static_cast<int>(s.height), static_cast<int>(s.width), CV_64F, cv::Scalar(0));
    std::vector<double> a;
    const int64_t channels = series.group().count;
    series.read(progress, [&](const PreparedTile& t) {
        const int64_t n = t.n;
        a.resize(static_cast<size_t>(std::max<int64_t>(rank, 1) * n));
        if (rank > 0) project_onto_basis(basis, rank, t.tile.data(), n, a.data());
        for (int64_t j = 0; j < n; ++j) {
            const auto p = static_cast<int>(t.range.begin + j / channels);
            double total = 0, kept = 0;
            for (int64_t f = 0; f < F; ++f) total += t.tile[f * n + j] * t.tile[f * n + j];
            for (int64_t i = 0; i < rank; ++i) {
                const double ai2 = a[i * n + j] * a[i * n + j];
                e.planes[i].at<double>(p) += ai2;
                kept += ai2;
            }
            e.tail.at<double>(p) += std::max(0.0, total - kept);
        }
    });
    return e;
}

void pool(cv::Mat& plane, int window) {
    if (window > 1) cv::boxFilter(plane, plane, -1, cv::Size(window, window), cv::Point(-1, -1), true, cv::BORDER_REFLECT);
}

class ErrorThresholdFilter final : public Filter {
public:
    ErrorThresholdFilter() : Filter(make_params()) {}

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {
            int_param("max_rank", "8", 1, 1000000, "most components a pixel may keep; the rest estimate the local noise"),
            float_param("threshold", "2", 0, 1e6,
                        "keep component i while its pooled energy exceeds threshold x the local noise energy"),
            int_param("window", "9", 1, 255, "side of the square window (pixels) over which coefficient energy is pooled"),
        };
        for (auto& c : temporal_common_params()) p.push_back(c);
        return p;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        const TemporalSetup setup = temporal_setup(params());
        const int64_t repaired = check_nonfinite(input, setup.nonfinite);
        const Shape& shape = input.shape();
        const auto groups = basis_groups(shape, setup.shared_basis);
        const double threshold = params().get_float("threshold");
        const int window = static_cast<int>(params().get_int("window"));
        auto rank_map = std::make_shared<Sequence>(Shape{1, shape.height, shape.width, static_cast<int64_t>(groups.size())});
        double rank_sum = 0;
        for (size_t g = 0; g < groups.size(); ++g) {
            const double share = 1.0 / groups.size(), at = g * share;
            PreparedSeries series(input, groups[g], setup.prep, setup.budget_bytes, 4);
            const TemporalBasis basis = compute_temporal_basis(series, {progress, at, 0.3 * share, "basis"});
            const int64_t useful = max_useful_rank(basis.series, basis.frames);
            const int64_t K = std::min(params().get_int("max_rank"), useful);
            CoefficientEnergy e = coefficient_energy(series, shape, basis, K,
                                                     {progress, at + 0.3 * share, 0.3 * share, "energy"});
            for (auto& plane : e.planes) pool(plane, window);
            pool(e.tail, window);
            // Noise energy one component carries: from the tail, or from the global estimate when
            // max_rank leaves no tail (few frames).
            const int64_t tail_components = useful - K;
            const double global_noise =
                std::pow(gavish_donoho_rank(basis.eigenvalues, basis.series, basis.frames).noise_sigma, 2) * groups[g].count;
            std::vector<int64_t> ranks(static_cast<size_t>(shape.pixels()));
            for (int64_t p = 0; p < shape.pixels(); ++p) {
                const double noise = tail_components > 0 ? e.tail.at<double>(static_cast<int>(p)) / tail_components : global_noise;
                int64_t k = 0;
                while (k < K && e.planes[k].at<double>(static_cast<int>(p)) > threshold * noise) ++k;
                ranks[p] = k;
                rank_sum += static_cast<double>(k);
                rank_map->at(0, p / shape.width, p % shape.width, static_cast<int64_t>(g)) = static_cast<float>(k);
            }
            reconstruct_low_rank(series, output, basis, K, &ranks,
                                  {progress, at + 0.6 * share, 0.4 * share, "reconstruct"});
        }
        for (size_t g = 0; g < groups.size(); ++g)
            rank_map->channel_names()[g] = groups.size() == 1 ? "rank" : "rank." + input.channel_names()[g];
        mutable_results().set("mean_rank", rank_sum / (static_cast<double>(shape.pixels()) * groups.size()));
        mutable_results().set("nonfinite_repaired", static_cast<double>(repaired));
        mutable_results().set_image("rank_map", rank_map);
    }

};

}  // namespace

std::unique_ptr<Filter> make_error_threshold_filter() { return std::make_unique<ErrorThresholdFilter>(); }

}  // namespace statfilter
