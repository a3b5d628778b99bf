// Global temporal PCA: every (pixel, channel) time series is replaced by its projection onto the
// top-k temporal components of the whole sequence, x_k = mu + V_k V_k^T (x - mu).
#include "filters/builtin_filters.hpp"
#include "filters/low_rank_filter.hpp"
#include "filters/temporal_params.hpp"

namespace statfilter {

namespace {

class PcaFilter final : public LowRankFilter {
public:
    PcaFilter() : LowRankFilter(make_params(), LowRankModel::Global) {}

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {rank_param("auto"), energy_param()};
        for (auto& s : temporal_common_params()) p.push_back(s);
        return p;
    }
};

}  // namespace

std::unique_ptr<Filter> make_pca_filter() { return std::make_unique<PcaFilter>(); }

}  // namespace statfilter
