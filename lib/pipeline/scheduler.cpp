// Filter::check and Filter::execute(source, sink): the scheduler's side of a filter.
#include "pipeline/scheduler.hpp"

#include <algorithm>
#include <mutex>
#include <vector>

#include "filters/frame_stages.hpp"
#include "pipeline/frame_stage_pool.hpp"
#include "pipeline/guide_sources.hpp"
#include "pipeline/memory_budget.hpp"
#include "pipeline/library_threads.hpp"
#include "pipeline/parallel.hpp"
#include "pipeline/scratch_frames.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/trusted_prefilter.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/nonfinite.hpp"
#include "statfilter/time_trust.hpp"

namespace statfilter {
namespace {

// The least scratch a single-frame stage's instance is given (OIDN's tiles: 256 MiB kept a 1080p frame
// within about a third of its time untiled, docs/streaming.md).
constexpr double kLeastStageShare = 256.0 * 1024 * 1024;

std::string shot_text(const Shape& s) {
    return std::to_string(s.frames) + " frames of " + std::to_string(s.width) + " x " + std::to_string(s.height) +
           " x " + std::to_string(s.channels);
}

}  // namespace

double frame_reserve_bytes(const ParamSet& stages, const Shape& s, int threads, bool files) {
    const double frame_bytes = static_cast<double>(s.pixels()) * s.channels * sizeof(float);
    // Per thread, a frame stage's frame and working set; with the trust blend, the noisy and the
    // prefiltered frame beside it and a probe's copy.
    const bool trusting = trusts_time_by_tile(stages);
    const double frame_stages = (has_frame_stage(stages, "prefilter") || runs_postfilter(stages))
                                    ? threads * (frame_stage_bytes(s) + (trusting ? 3 * frame_bytes : 0))
                                    : 0;
    // Reading and writing files, each thread may hold OpenImageIO's buffer of a frame's pixels in
    // the file's type being decoded and one being encoded: at most a float frame each. At 4K that
    // is 0.2 GiB a thread, so it is counted, not left to the fixed overhead.
    const double io_buffers = files ? 2.0 * threads * frame_bytes : 0.0;
    return frame_stages + io_buffers;
}

void Filter::set_provenance(FrameSink& sink) const {
    for (const char* name : {"method", "reason"})
        if (results_.has(name)) sink.set_attribute(std::string("statfilter:") + name, results_.get_string(name));
}

void Filter::check() const {
    const ParamSet stages = frame_stage_params();
    for (const char* stage : {"prefilter", "postfilter"})
        if (has_frame_stage(stages, stage)) make_frame_stage(stage, stages);
    check_prefilter_order(stages);
}

void Filter::execute(const FrameSource& source, FrameSink& sink, const RunOptions& options) {
    check();
    const Shape& s = source.shape();
    const int threads = resolve_threads(options.threads);
    const ThreadLimit limit(threads);
    const LibraryThreads pools(threads);
    const double budget = options.budget_bytes > 0 ? options.budget_bytes : static_cast<double>(default_memory_budget());
    const double frame_bytes = static_cast<double>(s.pixels()) * s.channels * sizeof(float);
    const ParamSet stages = frame_stage_params();  // the pools below hold a reference to it
    // prefilter_order=last: the stage works on the noisy frames and the prefilter runs again on each
    // frame it hands on, in place of the postfilter; without the trust blend it runs only then.
    const bool pre = has_frame_stage(stages, "prefilter"), post = runs_postfilter(stages);
    const bool last = prefilter_runs_last(stages);
    const bool prefilter_first = prefilters_noisy_shot(stages);
    std::unique_ptr<FrameStagePool> prefilter, postfilter;
    results_.clear();
    const Progress& progress = options.progress;

    double needed = 0;
    // A prefilter on samples to repair needs each series' mean first: such a run holds the shot.
    const bool repair_first = pre && nonfinite_policy_is(stages, "repair");
    const auto stage = repair_first ? nullptr : stream_stage();
    const bool streamed = stage != nullptr;
    if (stage) {
        if (pre) prefilter = std::make_unique<FrameStagePool>("prefilter", stages);
        if (post) postfilter = std::make_unique<FrameStagePool>("postfilter", stages);
        const bool trusting = trusts_time_by_tile(stages);
        const double reserved = frame_reserve_bytes(stages, s, threads, !source.in_memory());
        // A single-frame denoiser's own scratch (OIDN's: 3000 MiB an instance by default, whatever the
        // budget) is a share of the budget: each pool keeps up to one instance a thread, each given at
        // least kLeastStageShare and at most an equal part of half what the rest leaves, the other half
        // going to the stage's bands.
        const int sharing = (prefilter && prefilter->takes_memory_share() ? 1 : 0) +
                            (postfilter && postfilter->takes_memory_share() ? 1 : 0);
        const double instances = static_cast<double>(sharing) * threads;
        needed = stage->min_bytes(s, threads) + reserved + instances * kLeastStageShare;
        check_memory_budget(needed, budget, "this run (" + shot_text(s) + ", streamed)");
        // The renderer's passes, opened and checked against the input before any work.
        const OpenGuides guides = open_guide_sources(*this, source);
        double stage_shares = 0;
        if (sharing > 0) {
            const double each = std::max(kLeastStageShare, 0.5 * (budget - needed) / instances + kLeastStageShare);
            for (FrameStagePool* pool : {prefilter.get(), postfilter.get()})
                if (pool) pool->set_memory_share(each / (1024.0 * 1024.0));
            stage_shares = instances * each;
            results_.set("run.frame_stage_memory_each", each);
        }
        const FrameSource* input = &source;
        std::unique_ptr<ScratchFrames> scratch;
        std::unique_ptr<TimeTrust> trust;
        double start = 0;
        const auto samples = static_cast<size_t>(s.pixels() * s.channels);
        const Shape one{1, s.height, s.width, s.channels};
        if (prefilter_first) {
            // The temporal passes read bands of every prefiltered frame twice: park them on disk (run
            // last, the trust blend reads them back).
            start = 0.3;
            scratch = std::make_unique<ScratchFrames>(s, source.attributes());
            if (trusting) trust = std::make_unique<TimeTrust>(s, time_trust_options(stages));
            std::vector<std::vector<double>> noisy_light(static_cast<size_t>(s.frames)), filtered_light(noisy_light.size());
            // nonfinite=error is the pipeline's policy: the prefilter sees the frames first, and a NaN
            // fails here as it would in the temporal stage (naming the sample and the remedy), not
            // with the prefilter's own error.
            const bool refuse_nonfinite = nonfinite_policy_is(stages, "error");
            parallel_for(s.frames, threads, [&](int64_t f) {
                std::vector<float> frame(samples), noisy;
                source.read_rows(f, 0, s.height, frame.data());
                if (refuse_nonfinite) {
                    Sequence view(frame.data(), one, contiguous_strides(one));
                    view.channel_names() = source.attributes().channel_names();
                    view.frame_numbers()[0] = source.attributes().frame_numbers()[static_cast<size_t>(f)];
                    check_nonfinite(view, NonFinitePolicy::Error);
                }
                if (trust) noisy = frame;
                noisy_light[static_cast<size_t>(f)] = channel_sums(frame.data(), one);
                prefilter->apply(f, frame.data(), s, source.attributes());
                filtered_light[static_cast<size_t>(f)] = channel_sums(frame.data(), one);
                if (trust)
                    trust->probe(f, noisy.data(), frame.data(),
                                 [&](float* pixels) { prefilter->apply(f, pixels, s, source.attributes()); });
                scratch->write_frame(f, frame.data());
            }, {progress, 0.0, start, "prefilter"});
            if (keeps_prefilter_light(stages)) scratch->set_gain(light_gain(noisy_light, filtered_light));
            if (!last) input = scratch.get();
        }
        // With the trust blend the temporal frames wait on disk until every frame's fit is known; a
        // prefilter run last waits there too when its frames are scaled back to the light they had
        // (one gain per channel over the shot, known once every frame is through).
        const bool last_light = last && keeps_prefilter_light(stages);
        std::vector<std::vector<double>> before_last(last_light ? static_cast<size_t>(s.frames) : 0), after_last(before_last.size());
        std::unique_ptr<ScratchFrames> temporal;
        if (trust || last_light) temporal = std::make_unique<ScratchFrames>(s, source.attributes());
        // With the temporal result's probe the stage runs twice: each run half of what is left before
        // the blend (the second only when the first says it is needed: prepare_temporal_probe).
        const TimeTrustOptions trust_options = trust ? time_trust_options(stages) : TimeTrustOptions{};
        const bool may_probe = trust_options.temporal_probe != TimeTrustOptions::TemporalProbe::None;
        const double stage_end = may_probe ? start + 0.5 * (0.95 - start) : 1.0;
        const Progress stage_progress([&](double fraction, const char* name) {
            progress.report(start + (stage_end - start) * fraction, name);
            return true;
        });
        StageContext context;
        context.threads = threads;
        context.budget_bytes = budget - reserved - stage_shares;
        context.progress = &stage_progress;
        context.passes = guides.view;
        // What a preset picked is known before its first frame is handed on: the frames say so.
        std::once_flag provenance;
        stage->run(*input, [&](int64_t f, float* pixels) {
            if (last_light) before_last[static_cast<size_t>(f)] = channel_sums(pixels, one);
            if (last) prefilter->apply(f, pixels, s, source.attributes());
            if (last_light) after_last[static_cast<size_t>(f)] = channel_sums(pixels, one);
            if (temporal) {
                temporal->write_frame(f, pixels);
                return;
            }
            std::call_once(provenance, [&] { set_provenance(sink); });
            if (post) postfilter->apply(f, pixels, s, source.attributes());
            sink.write_frame(f, pixels);
        }, context, results_);
        const bool probe_temporal = trust && prepare_temporal_probe(*trust, trust_options, results_);
        if (temporal) {
            std::vector<float> gain;
            if (last_light) temporal->set_gain(gain = light_gain(before_last, after_last));
            if (probe_temporal) {
                // z = P(T(x)) depends on the noisy frame too: the stage and the prefilter once more, on
                // the probe's frames, scaled as z is, give the fit the rest of its Stein correction.
                const auto probed = probed_source(source, *trust);
                const Progress probe_progress([&](double fraction, const char* name) {
                    progress.report(stage_end + (0.95 - stage_end) * fraction, name);
                    return true;
                });
                StageContext again = context;
                again.progress = &probe_progress;
                Results ignored;  // the run's results are the first run's
                stage->run(*probed, [&](int64_t f, float* pixels) {
                    prefilter->apply(f, pixels, s, source.attributes());
                    if (!gain.empty()) scale_channels(pixels, one, gain);
                    std::vector<float> noisy(samples), prefiltered(samples), z(samples);
                    source.read_rows(f, 0, s.height, noisy.data());
                    scratch->read_rows(f, 0, s.height, prefiltered.data());
                    temporal->read_rows(f, 0, s.height, z.data());
                    trust->probe_temporal(f, noisy.data(), prefiltered.data(), z.data(), pixels);
                    // the fit's sums too, from the frames already read (its correction is complete)
                    trust->measure(f, noisy.data(), prefiltered.data(), z.data());
                }, again, ignored);
            }
            // The fit is measured on the frames as they will be blended (scaled), as in memory.
            if (trust && !probe_temporal)
                parallel_for(s.frames, threads, [&](int64_t f) {
                    std::vector<float> noisy(samples), prefiltered(samples), pixels(samples);
                    source.read_rows(f, 0, s.height, noisy.data());
                    scratch->read_rows(f, 0, s.height, prefiltered.data());
                    temporal->read_rows(f, 0, s.height, pixels.data());
                    trust->measure(f, noisy.data(), prefiltered.data(), pixels.data());
                }, {progress, 0.95, 0.025, "blend"});
            // Back towards the prefiltered frames where the noisy frames do not support the change.
            std::vector<double> share(static_cast<size_t>(s.frames), 1.0);
            parallel_for(s.frames, threads, [&](int64_t f) {
                std::vector<float> prefiltered, pixels(samples);
                temporal->read_rows(f, 0, s.height, pixels.data());
                if (trust) {
                    prefiltered.resize(samples);
                    scratch->read_rows(f, 0, s.height, prefiltered.data());
                    share[static_cast<size_t>(f)] = trust->blend(f, prefiltered.data(), pixels.data());
                }
                std::call_once(provenance, [&] { set_provenance(sink); });
                if (post) postfilter->apply(f, pixels.data(), s, source.attributes());
                sink.write_frame(f, pixels.data());
            }, {progress, 0.975, 0.025, trust ? "blend" : "write"});
            if (trust) {
                double mean = 0;
                for (double v : share) mean += v;
                results_.set("prefilter_trust.share", s.frames > 0 ? mean / static_cast<double>(s.frames) : 1.0);
            }
        }
    } else {
        // The whole shot in memory: input, output, the filter's own copies, and the stages' outputs;
        // the pixel tiles its passes prepare, which its memory_mb bounds (not the run's budget); and
        // what the streamed run sets aside too (the frame stages' working sets, the files' buffers).
        const double copies = 2 + resident_copies() + (pre ? 1 : 0) + (post ? 1 : 0);
        const double tiles = params().has("memory_mb") ? params().get_float("memory_mb") * 1024.0 * 1024.0 : 0.0;
        needed = (source.in_memory() ? copies - 1 : copies) * frame_bytes * static_cast<double>(s.frames) + tiles +
                 frame_reserve_bytes(stages, s, threads, !source.in_memory());
        // The renderer's passes, checked before the shot is read; run() reads those given as files
        // whole, beside the shot (up to 10 channels to its 3: more than the shot itself).
        const OpenGuides guides = open_guide_sources(*this, source);
        for (const FrameSource* pass : {guides.view.albedo, guides.view.normal, guides.view.vectors})
            if (pass && !pass->in_memory()) {
                const Shape& p = pass->shape();
                needed += static_cast<double>(p.frames) * static_cast<double>(p.pixels()) *
                          static_cast<double>(p.channels) * sizeof(float);
            }
        check_memory_budget(needed, budget, "this run (" + shot_text(s) + ", in memory: the filter needs the whole shot" +
                                                (guides.held.empty() ? "" : " and its passes") + ")");
        std::unique_ptr<Sequence> owned;
        const Sequence* input = source.in_memory();
        if (!input) {
            owned = std::make_unique<Sequence>(s);
            parallel_for(s.frames, threads, [&](int64_t f) { source.read_rows(f, 0, s.height, &owned->at(f, 0, 0, 0)); },
                         {progress, 0.0, 0.2, "read"});
            owned->copy_attributes_from(source.attributes());
            input = owned.get();
        }
        Sequence output(s);
        // execute runs the prefilter and postfilter itself, on the whole shot; what a preset picked is
        // known before the first frame is written, so the frames can say.
        execute(*input, output, Progress([&](double fraction, const char* name) {
            progress.report(0.2 + 0.7 * fraction, name);
            return true;
        }));
        set_provenance(sink);
        parallel_for(s.frames, threads, [&](int64_t f) { sink.write_frame(f, &output.at(f, 0, 0, 0)); },
                     {progress, 0.9, 0.1, "write"});
    }
    if (prefilter) prefilter->add_results(results_);
    if (postfilter) postfilter->add_results(results_);
    results_.set("run.frames", static_cast<double>(s.frames));
    results_.set("run.width", static_cast<double>(s.width));
    results_.set("run.height", static_cast<double>(s.height));
    results_.set("run.channels", static_cast<double>(s.channels));
    results_.set("run.streamed", streamed ? 1.0 : 0.0);
    results_.set("run.threads", static_cast<double>(threads));
    results_.set("run.memory_budget", budget);
    results_.set("run.memory_needed", needed);
    sink.commit();
    progress.report(1.0, "done");
}

}  // namespace statfilter
