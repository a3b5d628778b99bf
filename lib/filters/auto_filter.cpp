// Picks the method for the scene at the quality the user asks for (docs/benchmarks.md, "Presets",
// has the map these choices come from):
//   fast     - global temporal PCA (automatic rank): the cheapest filter that removes most of the
//              noise; it ghosts where things move.
//   balanced - measures how much of the frame moves (alpha) and runs the filter the benchmark found
//              most accurate for its cost on such a scene, then the diffusion postfilter:
//                (almost) nothing moves: global PCA, the cheapest and the best on a still camera
//                with changing light (cornell_light);
//                something moves: the error threshold method (per-pixel ranks keep what moves; the
//                hybrid is no better once both have the postfilter, at 2-3x the time).
//   high     - Intel Open Image Denoise on every frame first when its plugin can run here, then the
//              balanced choice on its output without the postfilter (after OIDN it changes nothing);
//              without OIDN, the hybrid wherever something moves, with the albedo/normal passes when
//              given.
// A postfilter the user names on this filter replaces the preset's (Filter::execute runs it).
// It says what it picked and why (results "method" and "reason").
#include <cstdio>

#include "filters/builtin_filters.hpp"
#include "filters/frame_stages.hpp"
#include "filters/motion_analysis.hpp"
#include "filters/temporal_params.hpp"
#include "statfilter/filter_registry.hpp"

namespace statfilter {
namespace {

// Why OIDN cannot run here, or empty when it can.
std::string oidn_problem() {
    for (const FilterEntry* entry : all_filters())
        if (entry->name == "oidn") return entry->available() ? "" : entry->problem;
    return "the oidn plugin is not installed";
}

class AutoFilter final : public Filter {
public:
    AutoFilter() : Filter(make_params()) {}

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = {
            choice_param("quality", "balanced", {"fast", "balanced", "high"},
                         "fast: global PCA; balanced: the method measured best for the scene's motion; high: "
                         "OIDN on every frame first (when available), then the best temporal method"),
            float_param("still_fraction", "0.01", 0, 1,
                        "below this share of moving pixels (1 - mean alpha) the scene counts as still"),
        };
        for (auto& c : motion_params()) p.push_back(c);
        for (auto& c : temporal_common_params()) p.push_back(c);
        return p;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        const std::string quality = params().get_string("quality");
        const bool passes = !params().get_string("albedo").empty() || !params().get_string("normal").empty();
        std::string method, reason;
        std::string prefilter;
        std::shared_ptr<Sequence> alpha;
        if (quality == "fast") {
            method = "pca";
            reason = "quality fast: global PCA, the cheapest filter; it may ghost where things move";
        } else {
            std::string oidn_note;
            if (quality == "high" && params().get_string("prefilter").empty()) {
                const std::string problem = oidn_problem();
                if (problem.empty())
                    prefilter = "oidn";
                else
                    oidn_note = " (OIDN not used: " + problem + ")";
            }
            // Only alpha decides: beta (z-scores or passes) is left to the hybrid if it is picked.
            alpha = compute_alpha(input, params(), {progress, 0.0, 0.3, "analyse"});
            const double moving = 1.0 - mean_of_map(*alpha);
            mutable_results().set("motion_fraction", moving);
            char share[32];
            std::snprintf(share, sizeof share, "%.1f%%", 100 * moving);
            const std::string prefix = "quality " + quality + ": " + share + " of pixels move";
            if (moving < params().get_float("still_fraction")) {
                method = "pca";
                reason = prefix + ", a still scene, where global PCA is cheapest and most accurate";
            } else if (!prefilter.empty()) {
                method = "error-threshold";
                reason = prefix + "; OIDN first, then per-pixel ranks keep the motion";
            } else if (quality == "high") {
                method = "hybrid";
                reason = prefix + (passes ? " and albedo/normal passes are given: the hybrid uses them"
                                          : ": the hybrid (no albedo/normal passes given)");
            } else {
                method = "error-threshold";
                reason = prefix + ": per-pixel ranks keep the motion (quality high adds OIDN or the hybrid)";
            }
            reason += oidn_note;
        }
        auto chosen = create_filter(method);
        for (const char* name : {"transform", "nonfinite", "shared_basis", "memory_mb"})
            chosen->params().set_string(name, params().get_string(name));
        if (method == "hybrid")
            for (const auto& spec : motion_params()) chosen->params().set_string(spec.name, params().get_string(spec.name));
        if (!prefilter.empty()) chosen->params().set_string("prefilter", prefilter);
        // The postfilter: the balanced preset's (the hybrid has its own by default), unless the user
        // named one here, which Filter::execute runs after this.
        const bool user_postfilter = !params().get_string("postfilter").empty();
        if (chosen->params().has("postfilter")) {
            const bool refine = quality == "balanced" && !user_postfilter;
            if (method != "hybrid" || user_postfilter) {
                chosen->params().set_string("postfilter", refine ? kRefinePostfilter : "");
                chosen->params().set_string("postfilter_params", refine ? kRefinePostfilterParams : "");
            }
        }
        const double start = alpha ? 0.3 : 0.0;
        chosen->execute(input, output, Progress([&](double f, const char* stage) {
            progress.report(start + (1 - start) * f, stage);
            return true;
        }));
        std::string picked = prefilter.empty() ? method : prefilter + " then " + method;
        if (!chosen->params().get_string("postfilter").empty())
            picked += " then " + chosen->params().get_string("postfilter");
        mutable_results().set("method", picked);
        mutable_results().set("reason", reason);
        mutable_results().set("quality", quality);
        for (const auto& name : chosen->results().names())
            if (name != "alpha" && name != "beta" && name != "rank_map")
                mutable_results().set(method + "." + name, chosen->results().get_string(name));
        if (alpha) mutable_results().set_image("alpha", alpha);
    }
};

}  // namespace

std::unique_ptr<Filter> make_auto_filter() { return std::make_unique<AutoFilter>(); }

}  // namespace statfilter
