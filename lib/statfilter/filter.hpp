// A filter reads one sequence and writes another of the same shape, configured by named parameters.
#pragma once
#include <map>
#include <set>
#include <memory>
#include <string>

#include "pipeline/footprint.hpp"
#include "statfilter/error.hpp"
#include "statfilter/params.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

class FrameSource;
class FrameSink;
class StreamStage;
struct RunOptions;

class Filter {
public:
    explicit Filter(std::vector<ParamSpec> params) : params_(std::move(params)) {}
    virtual ~Filter() = default;

    ParamSet& params() { return params_; }
    const ParamSet& params() const { return params_; }
    const Results& results() const { return results_; }

    // Checks shapes, runs the filter, and carries names, frame numbers and metadata to the output.
    void execute(const Sequence& input, Sequence& output, const Progress& progress);

    // Everything about the configuration that can be checked without data: the prefilter and
    // postfilter exist, are single-frame and take their parameters. Throws like execute would.
    void check() const;
    // Runs from a source to a sink: streamed when the filter has a stream stage (its pre- and
    // postfilter run frame by frame around it), else on the whole shot in memory. Everything
    // checkable is checked before the first frame is read, memory included (pipeline/scheduler.cpp).
    void execute(const FrameSource& source, FrameSink& sink, const RunOptions& options);

    // The filter's own work as a streaming stage, or null when it needs the whole shot in memory.
    virtual std::unique_ptr<StreamStage> stream_stage() const;
    // The parameters of the single-frame stages run around the filter's own work (prefilter,
    // postfilter, their order, the trust blend): its own, unless it picks a stage itself (quality
    // high picks OIDN).
    virtual ParamSet frame_stage_params() const { return params_; }
    // What the filter's own work reaches (without its pre/postfilter), and how many sequence-sized
    // buffers it holds besides its input and output when it runs in memory.
    virtual Footprint footprint() const { return {}; }
    virtual double resident_copies() const { return 2; }

    // Named extra inputs besides the main one (e.g. detect's "noisy"), as the filter declares them
    // with accept_input. Not owned: the caller keeps the sequence alive while it is set; nullptr
    // clears it. Unknown names throw Error(NotFound) listing the accepted ones.
    void set_input(const std::string& name, const Sequence* sequence) {
        if (!inputs_.count(name)) {
            std::string known;
            for (const auto& [n, s] : inputs_) known += (known.empty() ? "" : ", ") + n;
            throw Error(Status::NotFound, "this filter takes no input named '" + name + "'" +
                                              (known.empty() ? std::string(" (it takes none)") : " (inputs: " + known + ")"));
        }
        inputs_[name] = sequence;
        input_files_.erase(name);  // a sequence, or none: no files either
    }
    bool takes_input(const std::string& name) const { return inputs_.count(name) != 0; }
    std::vector<std::string> input_names() const {
        std::vector<std::string> names;
        for (const auto& [name, sequence] : inputs_) names.push_back(name);
        return names;
    }
    const Sequence* input(const std::string& name) const {
        auto it = inputs_.find(name);
        return it == inputs_.end() ? nullptr : it->second;
    }
    // A named input given as a frame sequence on disk (a file pattern with the main input's frames),
    // which a run from files reads a band or a frame at a time, never whole; "" clears it. It replaces
    // a sequence set under that name, and set_input (a sequence or nullptr) replaces or clears it.
    // Unknown names throw as set_input.
    void set_input_files(const std::string& name, const std::string& pattern) {
        set_input(name, nullptr);
        if (pattern.empty()) input_files_.erase(name);
        else input_files_[name] = pattern;
    }
    const std::string& input_files(const std::string& name) const {
        static const std::string none;
        auto it = input_files_.find(name);
        return it == input_files_.end() ? none : it->second;
    }

    // The image results the filter can produce (e.g. rank_map), so a request to save one can be checked
    // before any work; and whether one has a frame per frame of the shot (beta, mask) or is one image.
    const std::vector<std::string>& image_results() const { return image_results_; }
    bool image_result_per_frame(const std::string& name) const { return per_frame_images_.count(name) != 0; }

protected:
    void accept_input(const std::string& name) { inputs_.emplace(name, nullptr); }
    enum class ImageFrames { One, PerFrame };
    void declare_image_result(const std::string& name, ImageFrames frames = ImageFrames::One) {
        image_results_.push_back(name);
        if (frames == ImageFrames::PerFrame) per_frame_images_.insert(name);
    }
    virtual void run(const Sequence& input, Sequence& output, const Progress& progress) = 0;
    Results& mutable_results() { return results_; }

private:
    // The frames' provenance: what a preset picked and why (results method and reason).
    void set_provenance(FrameSink& sink) const;
    ParamSet params_;
    Results results_;
    std::map<std::string, const Sequence*> inputs_;
    std::map<std::string, std::string> input_files_;
    std::vector<std::string> image_results_;
    std::set<std::string> per_frame_images_;
};

// Checks, writing nothing, that image result `name` of `filter` can be written to `pattern` as a
// float image (a .png as its false-colour picture) after a run over the frames numbered shot_frames:
// a name the filter has, a frame token when the result has a frame per frame and the run more than
// one, the format, the directory (created when missing), and that no file it would write is a frame
// of input_pattern on disk or of other_pattern at those numbers (the run's output; "" = none). What
// the front ends do with every --save before the work.
void check_image_result_output(const Filter& filter, const std::string& name, const std::string& pattern,
                               const std::vector<int64_t>& shot_frames, const std::string& input_pattern,
                               const std::string& other_pattern);

}  // namespace statfilter
