// The identity filter: proves the path from file to C ABI to file, bit for bit.
#include "filters/builtin_filters.hpp"
#include "pipeline/frame_stream_stage.hpp"

namespace statfilter {
namespace {

class CopyFilter final : public Filter {
public:
    CopyFilter() : Filter({}) {}

    std::unique_ptr<StreamStage> stream_stage() const override {
        return std::make_unique<FrameStreamStage>([] { return make_copy_filter(); });
    }
    Footprint footprint() const override { return stream_stage()->footprint(); }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        progress.report(0.0, "copy");
        output.copy_samples_from(input);
        progress.report(1.0, "copy");
    }
};

}  // namespace

std::unique_ptr<Filter> make_copy_filter() { return std::make_unique<CopyFilter>(); }

}  // namespace statfilter
