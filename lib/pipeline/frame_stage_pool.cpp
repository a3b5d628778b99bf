#include "pipeline/frame_stage_pool.hpp"

#include <algorithm>

#include "filters/frame_stages.hpp"

namespace statfilter {

namespace {
constexpr const char* kShareParam = "max_memory_mb";
}

FrameStagePool::FrameStagePool(std::string stage, const ParamSet& params) : stage_(std::move(stage)), params_(params) {
    idle_.push_back(make_frame_stage(stage_, params_));
    takes_share_ = idle_.back()->params().has(kShareParam) && !names_param(params_.get_string(stage_ + "_params"), kShareParam);
}

std::unique_ptr<Filter> FrameStagePool::make() const {
    auto filter = make_frame_stage(stage_, params_);
    if (!share_.empty()) filter->params().set_string(kShareParam, share_);
    return filter;
}

void FrameStagePool::set_memory_share(double mib) {
    if (!takes_share_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    share_ = std::to_string(std::max<int64_t>(1, static_cast<int64_t>(mib)));
    for (auto& filter : idle_) filter->params().set_string(kShareParam, share_);
    if (last_) last_->params().set_string(kShareParam, share_);
}

void FrameStagePool::apply(int64_t f, float* pixels, const Shape& whole, const Sequence& attributes) {
    std::unique_ptr<Filter> filter;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!idle_.empty()) {
            filter = std::move(idle_.back());
            idle_.pop_back();
        }
    }
    if (!filter) filter = make();
    Sequence frame(pixels, Shape{1, whole.height, whole.width, whole.channels},
                   contiguous_strides(Shape{1, whole.height, whole.width, whole.channels}));
    frame.channel_names() = attributes.channel_names();
    frame.frame_numbers()[0] = attributes.frame_numbers()[static_cast<size_t>(f)];
    frame.source() = attributes.source();
    filter->execute(frame, frame, Progress());  // single-frame filters may work in place
    std::lock_guard<std::mutex> lock(mutex_);
    if (!keep_) {
        released_ = filter->results();
        last_.reset();
        return;  // filter, and its buffers, go here
    }
    if (last_) idle_.push_back(std::move(last_));
    last_ = std::move(filter);
}

void FrameStagePool::keep_buffers(bool keep) {
    if (!keep) release();  // the idle instances kept so far, with their buffers
    std::lock_guard<std::mutex> lock(mutex_);
    keep_ = keep;
}

void FrameStagePool::add_results(Results& results) const {
    add_stage_results(stage_, last_ ? last_->results() : released_, results);
}

void FrameStagePool::release() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (last_) released_ = last_->results();
    last_.reset();
    idle_.clear();
}

}  // namespace statfilter
