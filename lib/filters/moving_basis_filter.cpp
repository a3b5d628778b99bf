// Moving basis: each frame is denoised by a PCA of the frames around it, so the basis follows slow
// change instead of averaging the whole sequence into one. The work is the low-rank stage's, with
// the operator of pipeline/moving_basis_operator.hpp in place of the one basis: it streams, and a
// plan cuts it into tile tasks, as the global PCA.
#include "filters/builtin_filters.hpp"
#include "filters/low_rank_filter.hpp"
#include "filters/temporal_params.hpp"

namespace statfilter {

namespace {

class MovingBasisFilter final : public LowRankFilter {
public:
    MovingBasisFilter() : LowRankFilter(make_params(), LowRankModel::Moving) {}

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
};

}  // namespace

std::unique_ptr<Filter> make_moving_basis_filter() { return std::make_unique<MovingBasisFilter>(); }

}  // namespace statfilter
