// Picks the method for the scene: it measures how much of the frame moves (alpha) and runs the
// filter the benchmark found most accurate for such a scene (docs/benchmarks.md):
//   - (almost) nothing moves: global temporal PCA, the cheapest, and the best on a still camera
//     with changing light (cornell_light);
//   - something moves and the renderer's albedo/normal passes are given: the hybrid with them;
//   - something moves, no passes: the error threshold method (per-pixel ranks keep what moves).
// It says what it picked and why (results "method" and "reason").
#include "filters/builtin_filters.hpp"
#include "filters/motion_analysis.hpp"
#include "filters/temporal_params.hpp"
#include "statfilter/filter_registry.hpp"

namespace statfilter {
namespace {

class AutoFilter final : public Filter {
public:
    AutoFilter() : Filter(make_params()) {}

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {
            float_param("still_fraction", "0.01", 0, 1,
                        "below this share of moving pixels (1 - mean alpha) the scene counts as still"),
        };
        for (auto& c : motion_params()) p.push_back(c);
        for (auto& c : temporal_common_params()) p.push_back(c);
        return p;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        // Only alpha decides: beta (z-scores or passes) is left to the hybrid if it is picked.
        const auto alpha = compute_alpha(input, params(), {progress, 0.0, 0.3, "analyse"});
        const double moving = 1.0 - mean_of_map(*alpha);
        const bool passes = !params().get_string("albedo").empty() || !params().get_string("normal").empty();
        std::string method, reason;
        char share[32];
        std::snprintf(share, sizeof share, "%.1f%%", 100 * moving);
        if (moving < params().get_float("still_fraction")) {
            method = "pca";
            reason = std::string(share) + " of pixels move: a still scene, where global PCA is cheapest and most accurate";
        } else if (passes) {
            method = "hybrid";
            reason = std::string(share) + " of pixels move and albedo/normal passes are given: the hybrid uses them";
        } else {
            method = "error-threshold";
            reason = std::string(share) + " of pixels move, no albedo/normal passes: per-pixel ranks keep the motion";
        }
        auto chosen = create_filter(method);
        for (const char* name : {"transform", "nonfinite", "shared_basis", "memory_mb"})
            chosen->params().set_string(name, params().get_string(name));
        if (method == "hybrid")
            for (const auto& spec : motion_params()) chosen->params().set_string(spec.name, params().get_string(spec.name));
        chosen->execute(input, output, Progress([&](double f, const char* stage) {
            progress.report(0.3 + 0.7 * f, stage);
            return true;
        }));
        mutable_results().set("method", method);
        mutable_results().set("reason", reason);
        mutable_results().set("motion_fraction", moving);
        for (const auto& name : chosen->results().names())
            if (name != "alpha" && name != "beta" && name != "rank_map")
                mutable_results().set(method + "." + name, chosen->results().get_string(name));
        mutable_results().set_image("alpha", alpha);
    }
};

}  // namespace

std::unique_ptr<Filter> make_auto_filter() { return std::make_unique<AutoFilter>(); }

}  // namespace statfilter
