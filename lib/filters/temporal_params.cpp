#include "filters/temporal_params.hpp"

#include "filters/frame_stages.hpp"
#include "statfilter/nonfinite.hpp"

namespace statfilter {

std::vector<ParamSpec> temporal_common_params() {
    std::vector<ParamSpec> params = {
        // log measured best on every scene and level: docs/methods.md
        choice_param("transform", "log", {"none", "sqrt", "log"},
                     "variance-stabilising transform (signed) applied before the temporal basis and undone after"),
        // Leave-one-scene-out (docs/quality.md): firefly_z 8 is the pick; transform_scale's pick is 0.5
        // (2% lower relMSE), 2 keeps the hybrid's motion map (alpha) finding motion as it was tuned.
        float_param("transform_scale", "2", 0, 1e30,
                    "log/sqrt act on x / s with s = this x the median magnitude of the non-zero samples of the channels sharing "
                    "a basis, so results scale with the input; 0: s = 1 in the input's units (not scale-invariant)"),
        float_param("firefly_z", "8", 0, 1e6,
                    "a sample above its pixel's temporal median by more than this many robust deviations "
                    "(of log(1 + x / s)), or above its brightest neighbours by that many deviations of its "
                    "pixel's residual, alone among its neighbours, is a firefly: replaced by the median (of "
                    "its series, or of its neighbours) before the temporal model; 0 = off"),
        int_param("keep_mean", "1", 0, 1,
                  "1: the inverse transform keeps each series' linear mean (no Jensen bias) and a series "
                  "without negative samples non-negative, and a prefilter's output is scaled to the noisy shot's "
                  "light per channel (run last, to the light of the temporal result it is given); 0: the plain "
                  "inverse, the prefilter as it is"),
        choice_param("nonfinite", "error", {"error", "repair"},
                     "NaN/Inf input: fail naming the sample, or replace by the series' finite mean and count"),
        int_param("shared_basis", "1", 0, 1, "1: all channels share one temporal basis; 0: one basis per channel"),
        float_param("memory_mb", "512", 1, 1e7, "working memory budget for pixel tiles, in MiB (results do not depend on it)"),
    };
    for (auto& p : prefilter_params()) params.push_back(p);  // both run by Filter::execute
    for (auto& p : postfilter_params()) params.push_back(p);
    return params;
}

ParamSpec rank_param(const char* default_value) {
    ParamSpec s = choice_param("rank", default_value, {"auto", "energy"},
                               "temporal components kept: a count (0 = temporal mean), auto (Gavish-Donoho optimal "
                               "hard threshold), or energy (see 'energy')");
    s.accepts_integer = true;
    s.min = 0;
    s.max = 1000000;
    return s;
}

TemporalSetup temporal_setup(const ParamSet& params) {
    TemporalSetup t;
    t.prep.transform = parse_value_transform(params.get_string("transform"));
    t.nonfinite = parse_nonfinite_policy(params.get_string("nonfinite"));
    t.prep.repair_nonfinite = t.nonfinite == NonFinitePolicy::Repair;
    const double scale = params.get_float("transform_scale");
    t.prep.scale = scale > 0 ? 0.0 : 1.0;  // 0: measured from the data by PreparedSeries
    t.prep.scale_factor = scale > 0 ? scale : 1.0;
    t.prep.outlier_z = params.get_float("firefly_z");
    t.prep.keep_mean = params.get_int("keep_mean") != 0;
    t.shared_basis = params.get_int("shared_basis") != 0;
    t.budget_bytes = params.get_float("memory_mb") * 1024.0 * 1024.0;
    return t;
}

TemporalSetup temporal_setup(const ParamSet& params, const Sequence& input) {
    TemporalSetup t = temporal_setup(params);
    t.nonfinite_samples = check_nonfinite(input, t.nonfinite);
    return t;
}

std::vector<ChannelSelection> basis_groups(const Shape& shape, bool shared_basis) {
    if (shared_basis) return {ChannelSelection::all(shape)};
    std::vector<ChannelSelection> groups;
    for (int64_t c = 0; c < shape.channels; ++c) groups.push_back(ChannelSelection::one(c));
    return groups;
}

}  // namespace statfilter

namespace statfilter {

ParamSpec energy_param() {
    return float_param("energy", "0.99", 0, 1,
                       "with rank=energy: keep the fewest components holding this fraction of the variance");
}

RankChoice choose_rank(const ParamSet& params, const std::vector<double>& eigenvalues, int64_t series, int64_t frames) {
    RankChoice choice;
    const std::string& rank = params.get_string("rank");
    int64_t fixed = 0;
    if (rank == "auto") {
        choice = gavish_donoho_rank(eigenvalues, series, frames);
    } else if (rank == "energy") {
        choice.rank = energy_rank(eigenvalues, params.get_float("energy"));
    } else if (params.get_integer_choice("rank", fixed)) {
        choice.rank = fixed;
    }
    choice.rank = std::min(choice.rank, max_useful_rank(series, frames));
    return choice;
}

}  // namespace statfilter
