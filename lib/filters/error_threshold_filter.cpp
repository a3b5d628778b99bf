// The study's error threshold method: each pixel keeps its own number of temporal components.
// With an orthonormal basis, adding component i lowers a series' squared reconstruction error by
// exactly a_i^2 (its coefficient squared), so the Delta(error) test needs no reconstructions. One
// pixel's coefficients at low sample counts are mostly noise, so the test pools a_i^2 over a small
// window and compares it with the local noise level, estimated from the components beyond max_rank.
// The work is the streamed low-rank stage (pipeline/low_rank_stage.hpp) with per-pixel ranks.
#include "filters/builtin_filters.hpp"
#include "filters/low_rank_filter.hpp"
#include "filters/temporal_params.hpp"

namespace statfilter {
namespace {

class ErrorThresholdFilter final : public LowRankFilter {
public:
    ErrorThresholdFilter() : LowRankFilter(make_params(), LowRankModel::PerPixel) { declare_image_result("rank_map"); }

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
};

}  // namespace

std::unique_ptr<Filter> make_error_threshold_filter() { return std::make_unique<ErrorThresholdFilter>(); }

}  // namespace statfilter
