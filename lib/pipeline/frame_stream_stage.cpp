#include "pipeline/frame_stream_stage.hpp"

#include <mutex>
#include <vector>

#include "filters/frame_stages.hpp"
#include "pipeline/parallel.hpp"

namespace statfilter {

Footprint FrameStreamStage::footprint() const {
    Footprint f;
    f.reach = TemporalReach::Frame;
    f.streams = true;
    return f;
}

double FrameStreamStage::min_bytes(const Shape& s, int threads) const {
    return static_cast<double>(threads) * frame_stage_bytes(s);
}

void FrameStreamStage::run(const FrameSource& source, const FrameConsumer& consume, const StageContext& ctx,
                           Results& results) {
    const Shape& s = source.shape();
    const Shape one{1, s.height, s.width, s.channels};
    std::mutex mutex;
    std::vector<std::unique_ptr<Filter>> idle;
    std::unique_ptr<Filter> last;
    const Progress none;
    parallel_for(s.frames, ctx.threads, [&](int64_t f) {
        std::unique_ptr<Filter> filter;
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (!idle.empty()) {
                filter = std::move(idle.back());
                idle.pop_back();
            }
        }
        if (!filter) filter = make_();
        std::vector<float> pixels(static_cast<size_t>(s.pixels() * s.channels));
        source.read_rows(f, 0, s.height, pixels.data());
        Sequence frame(pixels.data(), one, contiguous_strides(one));
        frame.channel_names() = source.attributes().channel_names();
        frame.frame_numbers()[0] = source.attributes().frame_numbers()[static_cast<size_t>(f)];
        frame.source() = source.attributes().source();
        filter->execute(frame, frame, none);  // single-frame filters may work in place
        consume(f, pixels.data());
        std::lock_guard<std::mutex> lock(mutex);
        if (last) idle.push_back(std::move(last));
        last = std::move(filter);
    }, {ctx.progress ? *ctx.progress : none, 0, 1, "frames"});
    if (last)
        for (const auto& name : last->results().names()) {
            try {
                results.set(name, last->results().get_float(name));
            } catch (const Error&) {
                results.set(name, last->results().get_string(name));
            }
        }
}

}  // namespace statfilter
