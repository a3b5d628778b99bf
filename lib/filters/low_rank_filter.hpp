// The filters whose work is the streamed low-rank stage (pca; error-threshold with per-pixel ranks):
// the stage made from the parameters, its footprint, and the in-memory run through the same stage,
// written once for both.
#pragma once
#include <memory>
#include <vector>

#include "pipeline/low_rank_stage.hpp"
#include "pipeline/stage.hpp"
#include "statfilter/filter.hpp"

namespace statfilter {

class LowRankFilter : public Filter {
public:
    LowRankFilter(std::vector<ParamSpec> params, bool per_pixel_ranks)
        : Filter(std::move(params)), per_pixel_ranks_(per_pixel_ranks) {}

    std::unique_ptr<StreamStage> stream_stage() const override {
        return std::make_unique<LowRankStage>(low_rank_options(params(), per_pixel_ranks_));
    }
    Footprint footprint() const override { return stream_stage()->footprint(); }
    double resident_copies() const override { return 0; }  // pixel tiles and K coefficient images

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        run_in_memory(*stream_stage(), input, output, progress, params().get_float("memory_mb") * 1024.0 * 1024.0,
                      mutable_results());
    }

private:
    bool per_pixel_ranks_;
};

}  // namespace statfilter
