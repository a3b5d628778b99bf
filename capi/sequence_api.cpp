// sf_sequence_*: creating, wrapping, inspecting and releasing sequences.
#include <cstdint>
#include <cstring>

#include "api_guard.hpp"
#include "options.hpp"
#include "statfilter/false_colour.hpp"
#include "statfilter/metrics.hpp"

using namespace statfilter;
using namespace statfilter::capi;

namespace {

Shape to_shape(const sf_shape& s) { return Shape{s.frames, s.height, s.width, s.channels}; }

void check_index(int64_t index, int64_t count, const char* what) {
    if (index < 0 || index >= count)
        throw Error(Status::InvalidArgument, std::string(what) + " index " + std::to_string(index) + " is outside [0, " +
                                                 std::to_string(count) + ")");
}

// A caller's sample memory, checked before anything dereferences it: a reference to a misaligned
// float is undefined behaviour even before the Sequence's own alignment check could run.
float* require_samples(float* data, const char* what) {
    if (!data) throw Error(Status::InvalidArgument, std::string("argument '") + what + "' is NULL");
    if (reinterpret_cast<uintptr_t>(data) % alignof(float) != 0)
        throw Error(Status::InvalidArgument, std::string("argument '") + what + "' is not aligned to 4 bytes");
    return data;
}

sf_sequence new_handle(std::unique_ptr<Sequence> seq) {
    auto* handle = new sf_sequence_s;
    handle->sequence = std::move(seq);
    return handle;
}

}  // namespace

extern "C" {

sf_status sf_sequence_create(sf_shape shape, sf_sequence* out) {
    return guarded([&] {
        require(out, "out") = nullptr;
        *out = new_handle(std::make_unique<Sequence>(to_shape(shape)));
    });
}

sf_status sf_sequence_wrap(float* data, sf_shape shape, sf_strides strides, sf_sequence* out) {
    return guarded([&] {
        require(out, "out") = nullptr;
        *out = new_handle(std::make_unique<Sequence>(
            require_samples(data, "data"), to_shape(shape), Strides{strides.channel, strides.pixel, strides.row, strides.frame}));
    });
}

sf_status sf_sequence_release(sf_sequence sequence) {
    return guarded([&] { delete sequence; });
}

sf_status sf_sequence_shape(sf_sequence sequence, sf_shape* out) {
    return guarded([&] {
        const Shape& s = require_sequence(sequence, "sequence").shape();
        require(out, "out") = sf_shape{s.frames, s.height, s.width, s.channels};
    });
}

sf_status sf_sequence_data(sf_sequence sequence, float** data, sf_strides* strides) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        require(data, "data") = seq.data();
        const Strides& st = seq.strides();
        if (strides) *strides = sf_strides{st.channel, st.pixel, st.row, st.frame};
    });
}

sf_status sf_sequence_copy_to(sf_sequence sequence, float* dst, sf_strides dst_strides) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        Sequence target(require_samples(dst, "dst"), seq.shape(),
                        Strides{dst_strides.channel, dst_strides.pixel, dst_strides.row, dst_strides.frame});
        target.copy_samples_from(seq);
    });
}

sf_status sf_sequence_channel_name(sf_sequence sequence, int64_t channel, const char** name) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        require(name, "name");
        check_index(channel, seq.shape().channels, "channel");
        *name = seq.channel_names()[channel].c_str();
    });
}

sf_status sf_sequence_set_channel_name(sf_sequence sequence, int64_t channel, const char* name) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        require_string(name, "name");
        check_index(channel, seq.shape().channels, "channel");
        if (!*name) throw Error(Status::InvalidArgument, "channel name is empty");
        seq.channel_names()[channel] = name;
    });
}

sf_status sf_sequence_frame_number(sf_sequence sequence, int64_t index, int64_t* number) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        require(number, "number");
        check_index(index, seq.shape().frames, "frame");
        *number = seq.frame_numbers()[index];
    });
}

sf_status sf_sequence_set_frame_number(sf_sequence sequence, int64_t index, int64_t number) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        check_index(index, seq.shape().frames, "frame");
        seq.frame_numbers()[index] = number;
    });
}

sf_status sf_sequence_channel_stats(sf_sequence sequence, int64_t channel, sf_channel_stats* out) {
    return guarded([&] {
        Sequence& seq = require_sequence(sequence, "sequence");
        require(out, "out");
        const ChannelStats st = channel_stats(seq, channel);
        *out = sf_channel_stats{st.min, st.max, st.mean, st.nan_count, st.inf_count};
    });
}

}  // extern "C"

extern "C" {

void sf_comparison_init(sf_comparison* comparison) {
    if (!comparison) return;
    *comparison = sf_comparison{};
    comparison->struct_size = sizeof *comparison;
}

sf_status sf_sequence_compare(sf_sequence test, sf_sequence reference, sf_comparison* out) {
    return guarded([&] {
        sf_comparison& dst = require_versioned_out(out, "out");
        const Comparison c = compare_sequences(require_sequence(test, "test"), require_sequence(reference, "reference"));
        write_versioned(dst, sf_comparison{0, c.rel_mse, c.rel_mse_moving, c.rel_mse_static, c.moving_fraction,
                                           c.psnr, c.flicker, c.jitter});
    });
}

sf_status sf_sequence_false_colour(sf_sequence image, sf_sequence* preview) {
    return guarded([&] {
        require(preview, "preview") = nullptr;
        *preview = new sf_sequence_s{false_colour_preview(require_sequence(image, "image"))};
    });
}

}  // extern "C"
