// Global temporal PCA: every (pixel, channel) time series is replaced by its projection onto the
// top-k temporal components of the whole sequence, x_k = mu + V_k V_k^T (x - mu).
#include "filters/builtin_filters.hpp"
#include "filters/low_rank_reconstruction.hpp"
#include "filters/temporal_params.hpp"
#include "statfilter/error.hpp"

namespace statfilter {

namespace {

class PcaFilter final : public Filter {
public:
    PcaFilter() : Filter(make_params()) {}

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {rank_param("auto"), energy_param()};
        for (auto& s : temporal_common_params()) p.push_back(s);
        return p;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        const TemporalSetup setup = temporal_setup(params());
        const int64_t repaired = check_nonfinite(input, setup.nonfinite);
        const Shape& shape = input.shape();
        const auto groups = basis_groups(shape, setup.shared_basis);
        std::string ranks;
        double noise = 0;
        for (size_t g = 0; g < groups.size(); ++g) {
            const double share = 1.0 / groups.size();
            PreparedSeries series(input, groups[g], setup.prep, setup.budget_bytes, 3);
            const TemporalBasis basis = compute_temporal_basis(series, {progress, g * share, 0.5 * share, "basis"});
            const RankChoice rank = choose_rank(params(), basis.eigenvalues, basis.series, basis.frames);
            reconstruct_low_rank(series, output, basis, rank.rank, nullptr,
                                 {progress, (g + 0.5) * share, 0.5 * share, "reconstruct"});
            ranks += (ranks.empty() ? "" : ",") + std::to_string(rank.rank);
            noise = std::max(noise, rank.noise_sigma);
        }
        if (groups.size() == 1) {
            mutable_results().set("rank", std::stod(ranks));
        } else {
            mutable_results().set("rank", ranks);
        }
        if (params().get_string("rank") == "auto") mutable_results().set("noise_sigma", noise);
        mutable_results().set("nonfinite_repaired", static_cast<double>(repaired));
    }
};

}  // namespace

std::unique_ptr<Filter> make_pca_filter() { return std::make_unique<PcaFilter>(); }

}  // namespace statfilter
