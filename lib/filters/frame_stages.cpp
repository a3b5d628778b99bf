#include "filters/frame_stages.hpp"

#include <algorithm>

#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/error.hpp"
#include "statfilter/filter_registry.hpp"

namespace statfilter {

std::vector<ParamSpec> prefilter_params() {
    ParamSpec name = choice_param("prefilter", "", {},
                                  "single-frame filter run on every frame first (e.g. oidn, diffusion or a plugin); "
                                  "empty = none");
    ParamSpec list = choice_param("prefilter_params", "", {},
                                  "the prefilter's parameters as name=value,name=value (e.g. quality=high); "
                                  "its defaults otherwise");
    ParamSpec trust = int_param("prefilter_trust", "1", 0, 1,
                                "1: after the prefilter, each tile of a frame (prefilter_trust_tile) keeps only the share of the "
                                "temporal filter's change that its noisy frame supports (no ghost where the temporal "
                                "model fails; costs one more prefilter run per frame); 0: the temporal result as it is");
    // The trust blend's constants (statfilter/time_trust.hpp): defaults checked leave-one-scene-out
    // (docs/preset_loso.md).
    ParamSpec tile = int_param("prefilter_trust_tile", "16", 4, 256,
                               "the trust blend's tile side in pixels: one share of the temporal change per tile");
    ParamSpec pool = int_param("prefilter_trust_pool", "2", 0, 16,
                               "the trust blend's fit is pooled over frames t - this .. t + this");
    ParamSpec still_pool = int_param("prefilter_trust_pool_still", "8", 0, 64,
                                     "where the temporal filter followed no motion in a tile (it modelled it with the "
                                     "whole shot), the trust blend's fit is pooled over frames t - this .. t + this");
    ParamSpec probe = float_param("prefilter_trust_probe", "0.05", 0.001, 1,
                                  "the step of the trust blend's second prefilter run, in units of the tile's noise");
    ParamSpec order = choice_param("prefilter_order", "first", {"first", "last"},
                                   "first: the temporal filter works on the prefilter's frames; last: it works on the noisy "
                                   "frames and the prefilter runs on its result in place of the postfilter (the prefilter's "
                                   "frames of the noisy shot are then only what the trust blend falls back to)");
    // moving is the default: both lowers relMSE where time misleads (a camera dolly over textured
    // walls: 1.44x -> 1.10x OIDN's at 4 spp) but doubled the still-scene flicker, from its estimate of
    // a dependence the whole shot's model barely has; moving counts it only where the stage aligned
    // frames (docs/methods.md, "The temporal result's own dependence on the noisy frame").
    ParamSpec stein = choice_param("prefilter_trust_stein", "moving", {"prefilter", "moving", "both"},
                                   "with prefilter_order=last, what the trust blend's fit corrects for having been measured "
                                   "against the noisy frame both results were made from: prefilter (the prefilter's frame "
                                   "only: leans towards time, steadiest), both (the temporal result's too, everywhere: "
                                   "unbiased, more flicker where the scene is still) or moving (the temporal result's too "
                                   "where the temporal filter aligned frames along the motion, the prefilter's elsewhere). "
                                   "both and moving run the temporal filter and the prefilter once more on the probe's "
                                   "frames; moving only when something moves");
    return {name, list, trust, order, tile, pool, still_pool, probe, stein};
}

TimeTrustOptions time_trust_options(const ParamSet& params) {
    TimeTrustOptions o;
    o.tile = params.get_int("prefilter_trust_tile");
    o.pool = params.get_int("prefilter_trust_pool");
    o.still_pool = params.get_int("prefilter_trust_pool_still");
    o.probe = params.get_float("prefilter_trust_probe");
    const std::string stein = params.has("prefilter_trust_stein") ? params.get_string("prefilter_trust_stein") : "prefilter";
    if (stein != "prefilter" && prefilter_runs_last(params))
        o.temporal_probe = stein == "moving" ? TimeTrustOptions::TemporalProbe::WhereMoving
                                             : TimeTrustOptions::TemporalProbe::Everywhere;
    if (params.has("firefly_z")) o.outlier_z = params.get_float("firefly_z");
    return o;
}

std::vector<ParamSpec> postfilter_params(const char* default_filter, const char* default_params) {
    ParamSpec name = choice_param("postfilter", default_filter, {},
                                  "single-frame filter run on every frame of the result (e.g. diffusion: removes the "
                                  "spatially white noise a temporal basis leaves); empty = none");
    ParamSpec list = choice_param("postfilter_params", default_params, {},
                                  "the postfilter's parameters as name=value,name=value (e.g. iterations=3)");
    return {name, list};
}

double frame_stage_bytes(const Shape& s) {
    const double frame = static_cast<double>(s.pixels()) * s.channels * sizeof(float);
    return frame + std::max(5 * frame, diffusion_working_bytes(s.pixels(), s.channels));
}

bool has_frame_stage(const ParamSet& params, const std::string& stage) {
    return params.has(stage) && !params.get_string(stage).empty();
}

bool prefilter_runs_last(const ParamSet& params) {
    return has_frame_stage(params, "prefilter") && params.has("prefilter_order") &&
           params.get_string("prefilter_order") == "last";
}

bool prefilters_noisy_shot(const ParamSet& params) {
    return has_frame_stage(params, "prefilter") && (!prefilter_runs_last(params) || trusts_time_by_tile(params));
}

bool temporal_sees_prefilter(const ParamSet& params) {
    return has_frame_stage(params, "prefilter") && !prefilter_runs_last(params);
}

bool runs_postfilter(const ParamSet& params) {
    return has_frame_stage(params, "postfilter") && !prefilter_runs_last(params);
}

void check_prefilter_order(const ParamSet& params) {
    if (!prefilter_runs_last(params) || !has_frame_stage(params, "postfilter")) return;
    for (const auto& spec : params.specs())
        if (spec.name == "postfilter" && spec.default_value == params.get_string("postfilter")) return;
    throw Error(Status::InvalidArgument, "postfilter '" + params.get_string("postfilter") +
                                             "' does not run with prefilter_order=last: the prefilter runs on the temporal "
                                             "result in its place (prefilter_order=first runs both)");
}

bool keeps_prefilter_light(const ParamSet& params) {
    return has_frame_stage(params, "prefilter") && params.has("keep_mean") && params.get_int("keep_mean") != 0;
}

bool nonfinite_policy_is(const ParamSet& params, const char* policy) {
    return params.has("nonfinite") && params.get_string("nonfinite") == policy;
}

bool trusts_time_by_tile(const ParamSet& params) {
    return has_frame_stage(params, "prefilter") && params.has("prefilter_trust") && params.get_int("prefilter_trust") != 0;
}

namespace {

std::vector<std::pair<std::string, std::string>> parse_param_list(const std::string& list, const std::string& what) {
    std::vector<std::pair<std::string, std::string>> items;
    size_t start = 0;
    while (start < list.size()) {
        const size_t comma = std::min(list.find(',', start), list.size());
        const std::string piece = list.substr(start, comma - start);
        const size_t eq = piece.find('=');
        if (eq != std::string::npos && eq > 0) {
            items.emplace_back(piece.substr(0, eq), piece.substr(eq + 1));
        } else if (!items.empty()) {
            items.back().second += "," + piece;
        } else if (!piece.empty()) {
            throw Error(Status::InvalidArgument, what + ": expected name=value, got '" + piece + "'");
        }
        start = comma + 1;
    }
    return items;
}

}  // namespace

bool names_param(const std::string& list, const std::string& name) {
    for (const auto& item : parse_param_list(list, "a parameter list"))
        if (item.first == name) return true;
    return false;
}

void set_param_list(ParamSet& params, const std::string& list, const std::string& what) {
    for (const auto& [name, value] : parse_param_list(list, what)) {
        try {
            params.set_string(name, value);
        } catch (const Error& e) {
            throw Error(e.status(), what + ": " + e.what());
        }
    }
}

std::unique_ptr<Filter> make_frame_stage(const std::string& stage, const ParamSet& params) {
    const std::string& name = params.get_string(stage);
    const FilterEntry& entry = find_filter(name);
    auto filter = entry.create();  // a plugin that cannot be used throws its own error here
    if (entry.kind != FilterKind::SingleFrame)
        throw Error(Status::InvalidArgument, stage + " '" + name + "' is a temporal filter; a " + stage +
                                                 " works frame by frame (single-frame filters: see statfilter plugins)");
    set_param_list(filter->params(), params.get_string(stage + "_params"), stage + "_params");
    return filter;
}

void add_stage_results(const std::string& stage, const Results& own, Results& results) {
    for (const auto& result : own.names()) results.copy(own, result, stage + "." + result);
}

void run_frame_stage(const std::string& stage, const ParamSet& params, const Sequence& input, Sequence& output,
                     const Progress& progress, Results& results) {
    auto filter = make_frame_stage(stage, params);
    filter->execute(input, output, progress);
    add_stage_results(stage, filter->results(), results);
}

}  // namespace statfilter
