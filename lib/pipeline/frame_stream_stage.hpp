// A single-frame filter as a streaming stage: each frame read, filtered and handed on by itself,
// frames in parallel, each thread with an instance of its own.
#pragma once
#include <functional>
#include <memory>

#include "pipeline/stage.hpp"
#include "statfilter/filter.hpp"

namespace statfilter {

class FrameStreamStage final : public StreamStage {
public:
    // make: a configured instance of the filter (called once per thread that needs one).
    explicit FrameStreamStage(std::function<std::unique_ptr<Filter>()> make) : make_(std::move(make)) {}

    Footprint footprint() const override;
    double min_bytes(const Shape& shape, int threads) const override;
    void run(const FrameSource& source, const FrameConsumer& consume, const StageContext& context,
             Results& results) override;

private:
    std::function<std::unique_ptr<Filter>()> make_;
};

}  // namespace statfilter
