#include "pipeline/band_view.hpp"

#include "pipeline/parallel.hpp"

namespace statfilter {

std::unique_ptr<Sequence> band_view(const FrameSource& source, int64_t y0, int64_t y1, std::vector<float>& buffer,
                                    int threads, const ProgressSpan& progress) {
    const Shape& s = source.shape();
    const Shape band{s.frames, y1 - y0, s.width, s.channels};
    std::unique_ptr<Sequence> view;
    if (const Sequence* whole = source.in_memory()) {
        const Strides& st = whole->strides();
        float* origin = const_cast<float*>(whole->data());  // read only: PreparedSeries never writes its input
        view = std::make_unique<Sequence>(
            reinterpret_cast<float*>(reinterpret_cast<char*>(origin) + y0 * st.row), band, st);
    } else {
        const int64_t frame_floats = band.pixels() * band.channels;
        buffer.resize(static_cast<size_t>(frame_floats * band.frames));
        parallel_for(band.frames, threads,
                     [&](int64_t f) { source.read_rows(f, y0, y1, buffer.data() + f * frame_floats); },
                     progress);
        view = std::make_unique<Sequence>(buffer.data(), band, contiguous_strides(band));
    }
    view->frame_numbers() = source.attributes().frame_numbers();
    view->channel_names() = source.attributes().channel_names();
    return view;
}

std::unique_ptr<Sequence> rows_of_band(const Sequence& band, int64_t top, int64_t rows) {
    const Strides& st = band.strides();
    float* origin = const_cast<float*>(band.data());  // read only, as the band itself
    const Shape& b = band.shape();
    auto view = std::make_unique<Sequence>(reinterpret_cast<float*>(reinterpret_cast<char*>(origin) + top * st.row),
                                           Shape{b.frames, rows, b.width, b.channels}, st);
    view->frame_numbers() = band.frame_numbers();
    view->channel_names() = band.channel_names();
    return view;
}

}  // namespace statfilter
