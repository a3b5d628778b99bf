// The filters whose work is the streamed low-rank stage (pca; error-threshold with per-pixel ranks;
// moving-basis):
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
    LowRankFilter(std::vector<ParamSpec> params, LowRankModel model) : Filter(std::move(params)), model_(model) {}

    std::unique_ptr<StreamStage> stream_stage() const override {
        return std::make_unique<LowRankStage>(low_rank_options(params(), model_));
    }
    Footprint footprint() const override { return stream_stage()->footprint(); }
    // Pixel tiles and K coefficient images; the moving basis, its rebuilt shot before the frames go.
    double resident_copies() const override { return model_ == LowRankModel::Moving ? 1 : 0; }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        run_in_memory(*stream_stage(), input, output, progress, params().get_float("memory_mb") * 1024.0 * 1024.0,
                      mutable_results());
    }

private:
    LowRankModel model_;
};

}  // namespace statfilter
