#include "filters/motion_analysis.hpp"

#include <algorithm>

#include "filters/frame_stages.hpp"
#include "filters/temporal_params.hpp"
#include "pipeline/guide_sources.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/sequence_io.hpp"
#include "statfilter/value_transform.hpp"

namespace statfilter {

std::vector<ParamSpec> motion_params() {
    return {
        int_param("components", "5", 1, 1000, "leading temporal components whose energy marks global motion (the study: 5)"),
        choice_param("component_selection", "signal", {"signal", "fixed"},
                     "signal: of those, only the ones above the noise threshold (Gavish-Donoho rank) count; "
                     "fixed: all of them (the study)"),
        choice_param("alpha_noise", "local", {"local", "global"},
                     "noise unit of the component energy: the larger of the global noise and the pixel's own "
                     "(its energy beyond the components), or the global noise alone"),
        choice_param("global_light", "ignore", {"ignore", "keep"},
                     "ignore: remove what a global light change puts into the components before measuring motion"),
        float_param("alpha_low", "2", 0, 1e9, "component energy (in noise units) below which a pixel is stationary"),
        float_param("alpha_high", "8", 0, 1e9, "component energy (in noise units) above which a pixel is moving"),
        int_param("alpha_window", "5", 1, 255, "side of the box the component energy is averaged over"),
        float_param("z_threshold", "2.5", 0, 1e6, "local motion: robust z-score (window-averaged) above which a pixel moves"),
        int_param("z_window", "5", 1, 255, "local motion: side of the box the squared z-scores are averaged over"),
        int_param("dilate", "2", 0, 255, "local motion: dilation of the mask, in pixels"),
        choice_param("beta_source", "auto", {"auto", "zscore", "aux"},
                     "local motion from z-scores of the input, from the albedo/normal passes, or auto (the passes if given)"),
        ParamSpec{"albedo", ParamType::String, "", "albedo pass: a file pattern (frames as the input; of a multilayer file, its Albedo or DiffCol layer), or a layer of the input's files", 0, 0, {}, false, ""},
        ParamSpec{"normal", ParamType::String, "", "normal pass: a file pattern (frames as the input; of a multilayer file, its Normal layer), or a layer of the input's files", 0, 0, {}, false, ""},
        float_param("change_z", "5", 0, 1e6,
                    "temporal-change test (motion alpha misses, e.g. an object crossing a pixel in a frame or two): "
                    "robust score against the pixel's own noise above which it moves; 0 = off"),
        float_param("change_z_grow", "3", 0, 1e6,
                    "temporal-change test: a pixel scoring above this moves too when joined to one above change_z "
                    "through others that do (the rest of an object's path); 0 = not grown"),
        float_param("vector_drift", "0", 0, 1e9,
                    "with the renderer's motion vectors: a pixel they carry this many pixels over the shot moves; "
                    "0 = the vectors only align, the data says where things move (a surface sliding with no change "
                    "of its light keeps the temporal model)"),
        float_param("aux_threshold", "0.05", 0, 1e9, "a pass value departing this far from its temporal median means motion"),
    };
}

std::unique_ptr<Sequence> read_pass(const Sequence& input, const std::string& name, const std::string& pattern) {
    ReadOptions ro;
    ro.frames = format_frame_list(input.frame_numbers());
    const PassFiles files = pass_files(name, pattern, input);
    ro.channels = files.channels;
    auto aux = read_sequence(files.pattern, ro);
    const Shape& a = aux->shape();
    if (a.frames != input.shape().frames || a.width != input.shape().width || a.height != input.shape().height)
        throw Error(Status::InvalidArgument, "pass '" + pattern + "' is " + to_string(a) + ", the input " +
                                                 to_string(input.shape()));
    return aux;
}

namespace {

void check_pass(const Sequence& input, const Sequence& pass, const std::string& what) {
    const Shape& a = pass.shape();
    const Shape& s = input.shape();
    if (a.frames != s.frames || a.width != s.width || a.height != s.height)
        throw Error(Status::InvalidArgument, what + " is " + to_string(a) + ", the input " + to_string(s));
}

}  // namespace

void count_named_passes(const Filter& filter, const ParamSet& params, PassMotionOptions& options) {
    const auto named = [&](const std::string& name) {
        return filter.takes_input(name) &&
               (filter.input(name) || !filter.input_files(name).empty() ||
                (name != "vectors" && params.has(name) && !params.get_string(name).empty()));
    };
    options.named_vectors = named("vectors");
    options.named_surfaces = (named("albedo") ? 1 : 0) + (named("normal") ? 1 : 0);
}

GuidePasses guide_passes(const Filter& filter, const Sequence& input, const ParamSet& params) {
    GuidePasses g;
    g.albedo = filter.input("albedo");
    g.normal = filter.input("normal");
    g.vectors = filter.input("vectors");
    const auto read = [&](const char* name, const Sequence*& pass, std::shared_ptr<const Sequence>& held) {
        const std::string pattern = guide_pass_pattern(filter, params, name);
        if (pass || pattern.empty()) return;
        held = read_pass(input, name, pattern);
        pass = held.get();
    };
    read("albedo", g.albedo, g.read_albedo);
    read("normal", g.normal, g.read_normal);
    read("vectors", g.vectors, g.read_vectors);
    if (g.albedo) check_pass(input, *g.albedo, "the albedo pass");
    if (g.normal) check_pass(input, *g.normal, "the normal pass");
    if (g.vectors) {
        check_pass(input, *g.vectors, "the motion vectors");
        if (g.vectors->shape().channels < 4)
            throw Error(Status::InvalidArgument, "the motion vectors are " + to_string(g.vectors->shape()) +
                                                     ": expected 4 channels (X, Y, Z, W)");
    }
    return g;
}

GuideMemorySources guide_memory_sources(const GuidePasses& passes) {
    GuideMemorySources m;
    const auto wrap = [&](const Sequence* pass, const FrameSource*& into) {
        if (!pass) return;
        m.held.push_back(memory_source(*pass));
        into = m.held.back().get();
    };
    wrap(passes.albedo, m.view.albedo);
    wrap(passes.normal, m.view.normal);
    wrap(passes.vectors, m.view.vectors);
    return m;
}

TemporalChangeOptions temporal_change_options(const ParamSet& params, bool prefiltered) {
    TemporalChangeOptions o;
    o.z_threshold = params.get_float("change_z");
    o.grow_z = prefiltered ? 0.0 : params.get_float("change_z_grow");
    return o;
}

std::shared_ptr<Sequence> moving_weight(const Sequence& input, const Sequence& alpha, const GuidePasses& passes,
                                        const ParamSet& params, std::vector<float>* crossings,
                                        std::unique_ptr<TemporalChange>* change_test) {
    const Shape& s = input.shape();
    auto weight = std::make_shared<Sequence>(alpha.shape());
    weight->channel_names()[0] = "moving";
    for (int64_t y = 0; y < s.height; ++y)
        for (int64_t x = 0; x < s.width; ++x) weight->at(0, y, x, 0) = 1.0f - alpha.at(0, y, x, 0);
    const double z = params.get_float("change_z");
    if (z > 0) {
        auto test = temporal_change_test(input, temporal_change_options(params, temporal_sees_prefilter(params)));
        const auto change = test->map();
        if (crossings) *crossings = crossing_weight(*change, alpha);
        combine_max(*weight, *change);
        if (change_test) *change_test = std::move(test);
    } else {
        if (crossings) crossings->clear();
        if (change_test) change_test->reset();
    }
    // The renderer's albedo/normal passes change exactly where geometry moves, which noise cannot fake:
    // a pixel that departs from its temporal median in any frame (beta from the passes) moves.
    for (const Sequence* pass : {passes.albedo, passes.normal}) {
        if (!pass) continue;
        const auto beta = local_motion_from_aux(*pass, params.get_float("aux_threshold"), 0);
        for (int64_t f = 0; f < s.frames; ++f)
            for (int64_t y = 0; y < s.height; ++y)
                for (int64_t x = 0; x < s.width; ++x)
                    weight->at(0, y, x, 0) = std::max(weight->at(0, y, x, 0), beta->at(f, y, x, 0));
    }
    const double drift = params.get_float("vector_drift");
    if (passes.vectors && drift > 0) combine_max(*weight, *motion_from_vectors(*passes.vectors, drift));
    return weight;
}

std::vector<float> crossing_weight(const Sequence& change, const Sequence& alpha) {
    const Shape& s = alpha.shape();
    std::vector<float> weight(static_cast<size_t>(s.pixels()));
    for (int64_t p = 0; p < s.pixels(); ++p)
        weight[static_cast<size_t>(p)] = change.at(0, p / s.width, p % s.width, 0) * alpha.at(0, p / s.width, p % s.width, 0);
    return weight;
}

std::vector<int64_t> crossing_pixels(const std::vector<float>& weight) {
    std::vector<int64_t> pixels;
    for (size_t p = 0; p < weight.size(); ++p)
        if (weight[p] > 0.0f) pixels.push_back(static_cast<int64_t>(p));
    return pixels;
}

std::shared_ptr<Sequence> compute_alpha(PreparedSeries& series, const TemporalBasis& basis, const ParamSet& params,
                                        const ProgressSpan& progress) {
    const RankChoice rank = gavish_donoho_rank(basis.eigenvalues, basis.series, basis.frames);
    GlobalMotionOptions g;
    g.components = static_cast<int>(params.get_int("components"));
    // Components below the noise threshold are noise, and PCA aligns them with the noisiest pixels
    // (a few outlier samples): their energy piles up there and looks like motion.
    if (params.get_string("component_selection") == "signal")
        g.components = static_cast<int>(std::min<int64_t>(g.components, rank.rank));
    g.local_noise = params.get_string("alpha_noise") == "local";
    g.ignore_global_light = params.get_string("global_light") == "ignore";
    g.low = params.get_float("alpha_low");
    g.high = params.get_float("alpha_high");
    g.window = static_cast<int>(params.get_int("alpha_window"));
    if (!(g.high > g.low)) throw Error(Status::InvalidArgument, "alpha_high must be above alpha_low");
    return global_motion_map(series, basis, rank.noise_sigma, g, progress);
}

void compute_beta(const Sequence& input, const GuidePasses& passes, const ParamSet& params, MotionMaps& maps) {
    std::string source = params.get_string("beta_source");
    if (source == "auto") source = passes.surfaces() ? "aux" : "zscore";
    const int dilate = static_cast<int>(params.get_int("dilate"));
    if (source == "aux") {
        if (!passes.surfaces()) throw Error(Status::InvalidArgument, "beta_source=aux needs an albedo or normal pass");
        const double threshold = params.get_float("aux_threshold");
        for (const Sequence* pass : {passes.albedo, passes.normal}) {
            if (!pass) continue;
            auto beta = local_motion_from_aux(*pass, threshold, dilate);
            if (maps.beta) {
                combine_max(*maps.beta, *beta);
            } else {
                maps.beta = beta;
            }
        }
    } else {
        LocalMotionOptions l;
        l.z_threshold = params.get_float("z_threshold");
        l.window = static_cast<int>(params.get_int("z_window"));
        l.dilate = dilate;
        // In the units of the data, as the transform is: the same map at any exposure.
        const double factor = params.has("transform_scale") ? params.get_float("transform_scale") : 0.0;
        if (factor > 0) l.scale = factor * transform_level(input, ChannelSelection::all(input.shape()));
        maps.beta = local_motion_from_zscores(input, l);
    }
    maps.beta->frame_numbers() = input.frame_numbers();
    maps.beta_source = source;
}

std::shared_ptr<Sequence> compute_alpha(const Sequence& input, const ParamSet& params, const ProgressSpan& progress) {
    const TemporalSetup setup = temporal_setup(params, input);
    PreparedSeries series(input, ChannelSelection::all(input.shape()), setup.prep, setup.budget_bytes, 2);
    const TemporalBasis basis = compute_temporal_basis(series, {progress.progress, progress.start, progress.span / 2, "motion"});
    return compute_alpha(series, basis, params,
                         {progress.progress, progress.start + progress.span / 2, progress.span / 2, "motion"});
}

MotionMaps compute_motion(const Sequence& input, const GuidePasses& passes, const ParamSet& params,
                          const ProgressSpan& progress) {
    MotionMaps maps;
    maps.alpha = compute_alpha(input, params, {progress.progress, progress.start, progress.span * 2 / 3, "motion"});
    compute_beta(input, passes, params, maps);
    progress.report(1.0);
    return maps;
}

}  // namespace statfilter
