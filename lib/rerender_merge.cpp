#include "statfilter/rerender_merge.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"

namespace statfilter {

namespace {

std::map<int64_t, int64_t> frame_index(const Sequence& seq) {
    std::map<int64_t, int64_t> index;
    for (size_t i = 0; i < seq.frame_numbers().size(); ++i) index[seq.frame_numbers()[i]] = static_cast<int64_t>(i);
    return index;
}

void check_inputs(const Sequence& denoised, const Sequence& rerender, const MergeOptions& o, const Sequence& output) {
    const Shape& d = denoised.shape();
    if (output.shape() != d)
        throw Error(Status::InvalidArgument, "the merge output (" + to_string(output.shape()) +
                                                 ") must have the denoised sequence's shape (" + to_string(d) + ")");
    const Shape& r = rerender.shape();
    if (r.width != d.width || r.height != d.height)
        throw Error(Status::InvalidArgument, "the re-rendered frames are " + std::to_string(r.width) + " x " +
                                                 std::to_string(r.height) + ", the denoised frames " +
                                                 std::to_string(d.width) + " x " + std::to_string(d.height));
    if (r.channels != d.channels)
        throw Error(Status::InvalidArgument, "the re-rendered frames have " + std::to_string(r.channels) +
                                                 " channels, the denoised frames " + std::to_string(d.channels));
    const auto dindex = frame_index(denoised);
    for (int64_t number : rerender.frame_numbers())
        if (!dindex.count(number))
            throw Error(Status::InvalidArgument, "the re-render has frame " + std::to_string(number) +
                                                     ", which the denoised sequence does not have (frames " +
                                                     format_frame_list(denoised.frame_numbers()) + ")");
    if (!o.crops && !o.mask) throw Error(Status::InvalidArgument, "merge needs the crop windows, a mask, or both");
    if (o.feather < 0) throw Error(Status::InvalidArgument, "feather must be >= 0");
    if (o.crops) check_crop_plan(*o.crops, d.width, d.height, denoised.frame_numbers());
    if (o.mask) {
        const Shape& m = o.mask->shape();
        if (m.width != d.width || m.height != d.height)
            throw Error(Status::InvalidArgument, "the mask is " + std::to_string(m.width) + " x " +
                                                     std::to_string(m.height) + ", the denoised frames " +
                                                     std::to_string(d.width) + " x " + std::to_string(d.height));
        for (int64_t number : o.mask->frame_numbers())
            if (!dindex.count(number))
                throw Error(Status::InvalidArgument, "the mask has frame " + std::to_string(number) +
                                                         ", which the denoised sequence does not have (frames " +
                                                         format_frame_list(denoised.frame_numbers()) + ")");
    }
}

}  // namespace

int64_t merge_rerender(const Sequence& denoised, const Sequence& rerender, const MergeOptions& o, Sequence& output,
                       const Progress& progress) {
    check_inputs(denoised, rerender, o, output);
    const Shape& s = denoised.shape();
    const int H = static_cast<int>(s.height), W = static_cast<int>(s.width);
    const auto rindex = frame_index(rerender);
    const auto mindex = o.mask ? frame_index(*o.mask) : std::map<int64_t, int64_t>{};
    std::map<int64_t, const FrameCrops*> crops;
    if (o.crops)
        for (const FrameCrops& f : o.crops->frames) crops[f.frame] = &f;

    // First the regions of every frame, so that every error comes before any output is written.
    std::vector<cv::Mat> regions(static_cast<size_t>(s.frames));
    int64_t total = 0;
    for (int64_t f = 0; f < s.frames; ++f) {
        const int64_t number = denoised.frame_numbers()[static_cast<size_t>(f)];
        cv::Mat windows, mask;
        if (o.crops) {
            windows = cv::Mat::zeros(H, W, CV_8U);
            auto it = crops.find(number);
            if (it != crops.end())
                for (const CropWindow& w : it->second->windows)
                    windows(cv::Rect(static_cast<int>(w.x), static_cast<int>(w.y), static_cast<int>(w.width),
                                     static_cast<int>(w.height))) = 255;
        }
        if (o.mask) {
            mask = cv::Mat::zeros(H, W, CV_8U);
            auto it = mindex.find(number);
            if (it != mindex.end())
                for (int y = 0; y < H; ++y)
                    for (int x = 0; x < W; ++x) {
                        bool on = false;
                        for (int64_t c = 0; c < o.mask->shape().channels; ++c) on |= o.mask->at(it->second, y, x, c) != 0.0f;
                        if (on) mask.at<uint8_t>(y, x) = 255;
                    }
        }
        cv::Mat region = o.mask ? mask : windows;
        if (o.mask && o.crops) {
            const int outside = cv::countNonZero(mask & ~windows);
            if (outside > 0)
                throw Error(Status::InvalidArgument, "the mask flags " + std::to_string(outside) + " pixels of frame " +
                                                         std::to_string(number) +
                                                         " outside its crop windows: the windows must cover the mask "
                                                         "(were they made from another mask?)");
        }
        const int64_t count = cv::countNonZero(region);
        if (count == 0) continue;
        if (!rindex.count(number))
            throw Error(Status::InvalidArgument, "frame " + std::to_string(number) + " has " + std::to_string(count) +
                                                     " pixels to merge but the re-render has no frame " +
                                                     std::to_string(number));
        const int64_t r = rindex.at(number);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (!region.at<uint8_t>(y, x)) continue;
                for (int64_t c = 0; c < s.channels; ++c)
                    if (!std::isfinite(rerender.at(r, y, x, c)))
                        throw Error(Status::Numeric, "the re-render has NaN/Inf in frame " + std::to_string(number) +
                                                         " at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                         "), inside the region to merge");
            }
        regions[static_cast<size_t>(f)] = region;
        total += count;
    }
    if (total == 0)
        throw Error(Status::InvalidArgument, std::string("nothing to merge: ") +
                                                 (o.mask ? "the mask flags no pixel" : "the crop windows list no window") +
                                                 " (the denoised sequence is already the result)");

    if (&output != &denoised) output.copy_samples_from(denoised);
    for (int64_t f = 0; f < s.frames; ++f) {
        progress.report(static_cast<double>(f) / static_cast<double>(s.frames), "merge");
        const cv::Mat& region = regions[static_cast<size_t>(f)];
        if (region.empty()) continue;
        cv::Mat distance;
        if (o.feather > 0) cv::distanceTransform(region, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
        const int64_t number = denoised.frame_numbers()[static_cast<size_t>(f)];
        const int64_t r = rindex.at(number);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (!region.at<uint8_t>(y, x)) continue;
                // feather + 1 in float: any feather, up to INT64_MAX, is a weight, never an overflow.
                const float w = o.feather > 0
                                    ? std::min(1.0f, distance.at<float>(y, x) / (static_cast<float>(o.feather) + 1.0f))
                                    : 1.0f;
                for (int64_t c = 0; c < s.channels; ++c) {
                    const float d = denoised.at(f, y, x, c), v = rerender.at(r, y, x, c);
                    output.at(f, y, x, c) = w >= 1.0f ? v : d + w * (v - d);
                }
            }
    }
    progress.report(1.0, "merge");
    return total;
}

}  // namespace statfilter
