#include "pipeline/window_source.hpp"

#include <string>

#include "statfilter/error.hpp"
#include "statfilter/frame_metadata.hpp"

namespace statfilter {
namespace {

class RowWindow final : public FrameSource {
public:
    RowWindow(const FrameSource& base, int64_t y0, int64_t y1)
        : base_(base), y0_(y0), shape_{base.shape().frames, y1 - y0, base.shape().width, base.shape().channels} {}
    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return base_.attributes(); }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        base_.read_rows(f, y0_ + y0, y0_ + y1, dst);
    }

private:
    const FrameSource& base_;
    int64_t y0_;
    Shape shape_;
};

class FrameRange final : public FrameSource {
public:
    FrameRange(const FrameSource& base, int64_t first, int64_t last)
        : base_(base), first_(first), shape_{last - first, base.shape().height, base.shape().width, base.shape().channels},
          attributes_(frame_range_attributes(base.attributes(), first, last)) {}
    const Shape& shape() const override { return shape_; }
    const Sequence& attributes() const override { return *attributes_; }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        base_.read_rows(first_ + f, y0, y1, dst);
    }

private:
    const FrameSource& base_;
    int64_t first_;
    Shape shape_;
    std::unique_ptr<Sequence> attributes_;
};

void check_range(int64_t first, int64_t last, int64_t size, const char* what) {
    if (first < 0 || last > size || first >= last)
        throw Error(Status::InvalidArgument, std::string(what) + " [" + std::to_string(first) + ", " + std::to_string(last) +
                                                 ") is not inside [0, " + std::to_string(size) + ")");
}

}  // namespace

std::unique_ptr<FrameSource> row_window(const FrameSource& base, int64_t y0, int64_t y1) {
    check_range(y0, y1, base.shape().height, "rows");
    return std::make_unique<RowWindow>(base, y0, y1);
}

std::unique_ptr<FrameSource> frame_range(const FrameSource& base, int64_t first, int64_t last) {
    check_range(first, last, base.shape().frames, "frames");
    return std::make_unique<FrameRange>(base, first, last);
}

std::unique_ptr<Sequence> frame_range_attributes(const Sequence& attributes, int64_t first, int64_t last) {
    check_range(first, last, attributes.shape().frames, "frames");
    auto out = std::make_unique<Sequence>(Shape{last - first, 1, 1, attributes.shape().channels});
    out->channel_names() = attributes.channel_names();
    out->frame_numbers().assign(attributes.frame_numbers().begin() + first, attributes.frame_numbers().begin() + last);
    if (!attributes.metadata().empty())
        out->metadata().assign(attributes.metadata().begin() + first, attributes.metadata().begin() + last);
    out->source() = attributes.source();
    return out;
}

}  // namespace statfilter
