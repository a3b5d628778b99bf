// A single-frame filter (a prefilter or postfilter) applied to one frame at a time from several
// threads: each thread borrows an instance of its own, configured once from the parameters.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "statfilter/filter.hpp"

namespace statfilter {

class FrameStagePool {
public:
    // stage: "prefilter" or "postfilter"; params: the owning filter's parameters. Throws when the
    // stage cannot be made (checked before any work).
    FrameStagePool(std::string stage, const ParamSet& params);

    // Filters frame index f of a shot of `shape` in place: pixels are contiguous (row, pixel,
    // channel); attributes give its frame number, channel names and origin (for guide passes).
    void apply(int64_t f, float* pixels, const Shape& shape, const Sequence& attributes);
    // The stage's results ("STAGE.NAME") from the last frame filtered.
    void add_results(Results& results) const;
    // Lets every idle instance go, and the buffers it keeps for its next frame (a diffusion's): between
    // the phases of a stage that budget them apart. The results stay; the next apply makes new ones.
    void release();
    // Whether the stage takes a share of the run's memory budget: its filter has a max_memory_mb
    // parameter (a single-frame denoiser's own scratch, e.g. OIDN's, which tiles the frame to stay
    // within it) that the stage's parameter list leaves unset.
    bool takes_memory_share() const { return takes_share_; }
    // Each instance's share, in MiB: set on the idle instances and on every one made afterwards.
    void set_memory_share(double mib);
    // Whether an instance is kept for the next frame once it has filtered one (the default), with
    // the buffers it keeps; when the budget has no room for them, each frame's instance goes after it
    // (and the idle ones go now).
    void keep_buffers(bool keep);

private:
    std::string stage_;
    const ParamSet& params_;
    std::mutex mutex_;
    std::vector<std::unique_ptr<Filter>> idle_;
    std::unique_ptr<Filter> last_;
    Results released_;  // last_'s results once it is let go
    bool keep_ = true;
    bool takes_share_ = false;
    std::string share_;  // max_memory_mb for every instance, empty = the filter's own default

    std::unique_ptr<Filter> make() const;
};

}  // namespace statfilter
