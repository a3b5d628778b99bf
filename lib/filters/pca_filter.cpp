// Global temporal PCA: every (pixel, channel) time series is replaced by its projection onto the
// top-k temporal components of the whole sequence, x_k = mu + V_k V_k^T (x - mu).
#include "filters/builtin_filters.hpp"
#include "filters/temporal_params.hpp"
#include "pipeline/low_rank_stage.hpp"

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

    std::unique_ptr<StreamStage> stream_stage() const override {
        return std::make_unique<LowRankStage>(low_rank_options(params(), false));
    }
    Footprint footprint() const override { return stream_stage()->footprint(); }
    double resident_copies() const override { return 0; }  // pixel tiles and K coefficient images

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        run_in_memory(*stream_stage(), input, output, progress, params().get_float("memory_mb") * 1024.0 * 1024.0,
                      mutable_results());
    }
};

}  // namespace

std::unique_ptr<Filter> make_pca_filter() { return std::make_unique<PcaFilter>(); }

}  // namespace statfilter
