#include <cstring>

#include "pipeline/frame_source.hpp"

namespace statfilter {
namespace {

class MemorySource final : public FrameSource {
public:
    explicit MemorySource(const Sequence& s) : seq_(s), attributes_(Shape{s.shape().frames, 1, 1, s.shape().channels}) {
        attributes_.copy_attributes_from(s);
    }
    const Shape& shape() const override { return seq_.shape(); }
    const Sequence& attributes() const override { return attributes_; }
    const Sequence* in_memory() const override { return &seq_; }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        const Shape& s = seq_.shape();
        for (int64_t y = y0; y < y1; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) *dst++ = seq_.at(f, y, x, c);
    }

private:
    const Sequence& seq_;
    Sequence attributes_;
};

class MemorySink final : public FrameSink {
public:
    explicit MemorySink(Sequence& s) : seq_(s) {}
    void write_frame(int64_t f, const float* pixels) override { seq_.set_frame(f, pixels); }
    void commit() override {}

private:
    Sequence& seq_;
};

}  // namespace

std::unique_ptr<FrameSource> memory_source(const Sequence& sequence) { return std::make_unique<MemorySource>(sequence); }
std::unique_ptr<FrameSink> memory_sink(Sequence& sequence) { return std::make_unique<MemorySink>(sequence); }

}  // namespace statfilter
