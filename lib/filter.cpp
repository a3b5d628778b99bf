#include "statfilter/filter.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "filters/frame_stages.hpp"
#include "pipeline/library_threads.hpp"
#include "pipeline/parallel.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/trusted_prefilter.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/nonfinite.hpp"
#include "statfilter/sequence_io.hpp"

namespace statfilter {

namespace fs = std::filesystem;

namespace {

// A slice [start, start + span) of a parent's progress, as a Progress of its own.
Progress slice(const Progress& parent, double start, double span) {
    return Progress([&parent, start, span](double fraction, const char* stage) {
        parent.report(start + span * fraction, stage);  // throws when the parent cancels
        return true;
    });
}

}  // namespace

std::unique_ptr<StreamStage> Filter::stream_stage() const { return nullptr; }

void Filter::execute(const Sequence& input, Sequence& output, const Progress& progress) {
    if (input.shape() != output.shape())
        throw Error(Status::InvalidArgument, "output shape (" + to_string(output.shape()) +
                                                 ") differs from input shape (" + to_string(input.shape()) + ")");
    const ParamSet stages = frame_stage_params();  // the pools below hold a reference to it
    check_prefilter_order(stages);
    results_.clear();
    const LibraryThreads pools(resolve_threads(0));
    // Filters with prefilter/postfilter parameters (the temporal ones) run between those stages.
    // prefilter_order=last: the temporal filter works on the noisy frames and the prefilter runs again
    // on its result, in place of the postfilter.
    const bool pre = has_frame_stage(stages, "prefilter"), post = runs_postfilter(stages);
    const bool last = prefilter_runs_last(stages);
    const bool prefilter_first = prefilters_noisy_shot(stages);
    const double pre_span = prefilter_first ? 0.4 : 0.0, post_span = (post || last) ? 0.2 : 0.0;
    std::unique_ptr<Sequence> prefiltered, filtered;
    const Sequence* source = &input;
    // nonfinite=repair is the pipeline's policy, not only the temporal filter's: a prefilter (OIDN
    // refuses NaN) gets the samples repaired the same way (each series' finite mean) first.
    std::unique_ptr<Sequence> repaired;
    if (pre && nonfinite_policy_is(stages, "repair") &&
        check_nonfinite(input, NonFinitePolicy::Repair) > 0) {
        repaired = std::make_unique<Sequence>(input.shape());
        repaired->copy_samples_from(input);
        repaired->copy_attributes_from(input);
        repair_sequence_nonfinite(*repaired);
        source = repaired.get();
    }
    const Sequence* noisy = source;
    // nonfinite=error: a NaN fails naming the sample and the remedy before the prefilter meets it.
    if (prefilter_first && nonfinite_policy_is(stages, "error"))
        check_nonfinite(*source, NonFinitePolicy::Error);
    std::unique_ptr<TimeTrust> trust;
    if (prefilter_first) {  // the stage's execute gives it input's attributes
        prefiltered = std::make_unique<Sequence>(input.shape());
        if (trusts_time_by_tile(stages)) {  // frame by frame, each probed once more
            trust = std::make_unique<TimeTrust>(input.shape(), time_trust_options(stages));
            FrameStagePool pool("prefilter", stages);
            prefilter_and_probe(pool, *source, *prefiltered, *trust, resolve_threads(0), {progress, 0, pre_span, "prefilter"});
            pool.add_results(results_);
        } else {
            run_frame_stage("prefilter", stages, *source, *prefiltered, slice(progress, 0, pre_span), results_);
        }
        if (keeps_prefilter_light(stages)) keep_prefilter_light(*noisy, *prefiltered, resolve_threads(0));
        if (!last) source = prefiltered.get();
    }
    Sequence* target = &output;
    if (post) {
        filtered = std::make_unique<Sequence>(input.shape());
        target = filtered.get();
    }
    run(*source, *target, slice(progress, pre_span, 1 - pre_span - post_span));
    const bool probe_temporal = trust && prepare_temporal_probe(*trust, time_trust_options(stages), results_);
    if (last) {  // the prefilter on the temporal result, scaled back to its light (the noisy shot's)
        FrameStagePool pool("prefilter", stages);
        const std::vector<float> gain =
            filter_frames(pool, *target, *noisy, resolve_threads(0), {progress, 1 - post_span, post_span, "prefilter"},
                          keeps_prefilter_light(stages));
        pool.add_results(results_);
        if (probe_temporal) {
            // z = P(T(x)) depends on the noisy frame too: T and P once more on the probe's frames,
            // scaled as z was, give the fit the rest of its Stein correction (as the streamed run).
            Sequence probed(input.shape());
            probed.copy_attributes_from(*noisy);
            const auto noisy_source = memory_source(*noisy);
            const auto from = probed_source(*noisy_source, *trust);
            for (int64_t f = 0; f < input.shape().frames; ++f)
                from->read_rows(f, 0, input.shape().height, &probed.at(f, 0, 0, 0));
            Sequence again(input.shape());
            const Results kept = results_;  // the run's results are the first run's
            run(probed, again, slice(progress, 1 - post_span, 0));
            results_ = kept;
            filter_frames(pool, again, *noisy, resolve_threads(0), {progress, 1 - post_span, 0, "prefilter"}, false);
            if (!gain.empty()) scale_channels(again, gain, resolve_threads(0));
            probe_temporal_result(*trust, *noisy, *prefiltered, *target, again, resolve_threads(0));
        }
    }
    if (trust) results_.set("prefilter_trust.share", blend_toward_prefilter(*trust, *noisy, *prefiltered, *target, resolve_threads(0)));
    if (post) run_frame_stage("postfilter", stages, *filtered, output, slice(progress, 1 - post_span, post_span), results_);
    if (&input != &output) output.copy_attributes_from(input);
}

void check_image_result_output(const Filter& filter, const std::string& name, const std::string& pattern,
                               const std::vector<int64_t>& shot_frames, const std::string& input_pattern,
                               const std::string& other_pattern) {
    const std::vector<std::string>& names = filter.image_results();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string known;
        for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
        throw Error(Status::InvalidArgument, "the filter has no image result '" + name + "' (it has: " +
                                                 (known.empty() ? std::string("none") : known) + ")");
    }
    const auto refuse = [&](const std::string& why) {
        throw Error(Status::InvalidArgument, "image result '" + name + "': " + why);
    };
    // The pattern, the format and the directory as the writer checks them; only "more than one frame"
    // matters for the frame token, so two frames stand for many.
    const int64_t count = static_cast<int64_t>(shot_frames.size());
    const bool per_frame = filter.image_result_per_frame(name);
    if (per_frame && count > 1 && !FramePattern(pattern).has_frame_token())
        refuse("output pattern '" + pattern + "' has no frame token (#, @ or %0Nd) but the result has " +
               std::to_string(count) + " frames, one per frame of the run");
    const int64_t frames = per_frame ? std::min<int64_t>(2, std::max<int64_t>(1, count)) : 1;
    Sequence attributes(Shape{frames, 1, 1, 1});
    for (int64_t f = 0; f < frames; ++f) attributes.frame_numbers()[static_cast<size_t>(f)] = f + 1;
    WriteOptions as_float;
    as_float.half = false;
    OutputChecks checks;
    checks.width = checks.height = 1;
    try {
        open_frame_sink(pattern, as_float, attributes, checks);
    } catch (const Error& e) {
        refuse(e.what());
    }
    // Never over a frame of the input on disk, nor over one of other_pattern's at the run's frame
    // numbers (its output's): the files the result would go to, by name or as the same file.
    const auto normal = [](const std::string& p) { return fs::absolute(p).lexically_normal().string(); };
    const FramePattern image(pattern);
    std::set<std::string> written;
    if (!image.has_frame_token()) written.insert(normal(pattern));
    else
        for (int64_t n : shot_frames) written.insert(normal(image.format(n)));
    std::map<std::string, std::string> taken;  // a frame's file -> its sequence's pattern
    std::vector<std::string> inputs;
    if (!input_pattern.empty()) {
        const FramePattern input(input_pattern);
        std::vector<int64_t> on_disk;
        try {
            on_disk = input.scan();
        } catch (const Error&) {
        }  // none: the run says so before any work
        for (int64_t n : on_disk) {
            inputs.push_back(input.format(n));
            taken.emplace(normal(inputs.back()), input_pattern);
        }
    }
    if (!other_pattern.empty())
        for (int64_t n : shot_frames) taken.emplace(normal(FramePattern(other_pattern).format(n)), other_pattern);
    for (const std::string& file : written) {
        const auto it = taken.find(file);
        if (it != taken.end()) refuse("'" + file + "' is a frame of '" + it->second + "': refusing to write over it");
        std::error_code ec;
        if (!fs::exists(file, ec)) continue;
        for (const std::string& in : inputs)
            if (fs::equivalent(file, in, ec)) refuse("'" + file + "' is the input frame '" + in + "': refusing to write over it");
    }
}

}  // namespace statfilter
