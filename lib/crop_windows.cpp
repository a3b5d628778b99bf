#include "statfilter/crop_windows.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"
#include "statfilter/json.hpp"

namespace statfilter {

int64_t CropPlan::flagged() const {
    int64_t n = 0;
    for (const auto& f : frames) n += f.flagged;
    return n;
}

int64_t CropPlan::window_pixels() const {
    int64_t n = 0;
    for (const auto& f : frames)
        for (const auto& w : f.windows) n += w.area();
    return n;
}

int64_t CropPlan::window_count() const {
    int64_t n = 0;
    for (const auto& f : frames) n += static_cast<int64_t>(f.windows.size());
    return n;
}

int64_t CropPlan::cost_pixels() const { return window_pixels() + window_count() * options.window_cost; }

namespace {

CropWindow bounding_box(const CropWindow& a, const CropWindow& b) {
    const int64_t x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
    const int64_t x1 = std::max(a.x + a.width, b.x + b.width), y1 = std::max(a.y + a.height, b.y + b.height);
    return {x0, y0, x1 - x0, y1 - y0};
}

int64_t overlap(const CropWindow& a, const CropWindow& b) {
    const int64_t w = std::min(a.x + a.width, b.x + b.width) - std::max(a.x, b.x);
    const int64_t h = std::min(a.y + a.height, b.y + b.height) - std::max(a.y, b.y);
    return w > 0 && h > 0 ? w * h : 0;
}

// Grows [start, start + size) to at least `minimum` within [0, limit), keeping it centred if it can.
void grow(int64_t& start, int64_t& size, int64_t minimum, int64_t limit) {
    const int64_t target = std::min(minimum, limit);
    if (size >= target) return;
    start -= (target - size) / 2;
    size = target;
    start = std::clamp<int64_t>(start, 0, limit - size);
}

// With very many windows, first merge those in the same cell of a grid (coarser until at most
// `limit` remain), so that the pairwise merging stays cheap.
void coarsen(std::vector<CropWindow>& windows, int64_t height, int64_t width, size_t limit) {
    for (int64_t cell = 16; windows.size() > limit; cell *= 2) {
        std::vector<CropWindow> merged;
        std::vector<int64_t> slot;
        const int64_t cols = (width + cell - 1) / cell, rows = (height + cell - 1) / cell;
        std::vector<int64_t> index(static_cast<size_t>(cols * rows), -1);
        for (const auto& w : windows) {
            const int64_t c = std::min(cols - 1, (w.x + w.width / 2) / cell), r = std::min(rows - 1, (w.y + w.height / 2) / cell);
            int64_t& i = index[static_cast<size_t>(r * cols + c)];
            if (i < 0) {
                i = static_cast<int64_t>(merged.size());
                merged.push_back(w);
            } else {
                merged[static_cast<size_t>(i)] = bounding_box(merged[static_cast<size_t>(i)], w);
            }
        }
        windows.swap(merged);
    }
}

void merge_windows(std::vector<CropWindow>& windows, int64_t window_cost) {
    while (windows.size() > 1) {
        size_t best_i = 0, best_j = 0;
        bool found = false, best_overlaps = false;
        int64_t best_extra = std::numeric_limits<int64_t>::max();
        for (size_t i = 0; i < windows.size(); ++i)
            for (size_t j = i + 1; j < windows.size(); ++j) {
                const int64_t ov = overlap(windows[i], windows[j]);
                // Pixels the bounding box adds beyond what the two windows already cover.
                const int64_t extra = bounding_box(windows[i], windows[j]).area() - (windows[i].area() + windows[j].area() - ov);
                const bool overlaps = ov > 0;
                if (!overlaps && extra > window_cost) continue;
                if (!found || (overlaps && !best_overlaps) || (overlaps == best_overlaps && extra < best_extra)) {
                    found = true;
                    best_overlaps = overlaps;
                    best_extra = extra;
                    best_i = i;
                    best_j = j;
                }
            }
        if (!found) break;
        windows[best_i] = bounding_box(windows[best_i], windows[best_j]);
        windows.erase(windows.begin() + static_cast<std::ptrdiff_t>(best_j));
    }
}

}  // namespace

std::vector<CropWindow> cover_mask(const std::vector<uint8_t>& mask, int64_t height, int64_t width,
                                   const CropOptions& o) {
    if (static_cast<int64_t>(mask.size()) != height * width)
        throw Error(Status::InvalidArgument, "mask size does not match its dimensions");
    if (o.padding < 0 || o.min_size < 1 || o.window_cost < 0)
        throw Error(Status::InvalidArgument, "crop padding and window cost must be >= 0, the minimum size >= 1");
    std::vector<CropWindow> windows;
    if (std::none_of(mask.begin(), mask.end(), [](uint8_t v) { return v != 0; })) return windows;
    cv::Mat m(static_cast<int>(height), static_cast<int>(width), CV_8U);
    for (int64_t i = 0; i < height * width; ++i) m.data[i] = mask[static_cast<size_t>(i)] ? 255 : 0;
    if (o.padding > 0) {
        const int r = static_cast<int>(std::min<int64_t>(o.padding, std::max(height, width)));
        cv::dilate(m, m, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1)), cv::Point(-1, -1), 1,
                   cv::BORDER_CONSTANT, cv::Scalar(0));
    }
    cv::Mat labels, stats, centroids;
    const int count = cv::connectedComponentsWithStats(m, labels, stats, centroids, 8, CV_32S);
    for (int k = 1; k < count; ++k) {
        CropWindow w{stats.at<int>(k, cv::CC_STAT_LEFT), stats.at<int>(k, cv::CC_STAT_TOP),
                     stats.at<int>(k, cv::CC_STAT_WIDTH), stats.at<int>(k, cv::CC_STAT_HEIGHT)};
        grow(w.x, w.width, o.min_size, width);
        grow(w.y, w.height, o.min_size, height);
        windows.push_back(w);
    }
    coarsen(windows, height, width, 512);
    merge_windows(windows, o.window_cost);
    std::sort(windows.begin(), windows.end(),
              [](const CropWindow& a, const CropWindow& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
    return windows;
}

CropPlan make_crop_plan(const Sequence& mask, const CropOptions& options) {
    const Shape& s = mask.shape();
    CropPlan plan;
    plan.width = s.width;
    plan.height = s.height;
    plan.frame_count = s.frames;
    plan.options = options;
    std::vector<uint8_t> frame(static_cast<size_t>(s.pixels()));
    for (int64_t f = 0; f < s.frames; ++f) {
        int64_t flagged = 0;
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x) {
                bool on = false;
                for (int64_t c = 0; c < s.channels; ++c) on |= mask.at(f, y, x, c) != 0.0f;
                frame[static_cast<size_t>(y * s.width + x)] = on;
                flagged += on;
            }
        if (!flagged) continue;
        plan.frames.push_back({mask.frame_numbers()[static_cast<size_t>(f)], flagged,
                               cover_mask(frame, s.height, s.width, options)});
    }
    return plan;
}

namespace {

// The schema this statfilter writes and reads (docs/crops.md, docs/crops.schema.json).
constexpr int64_t kCropsSchemaVersion = 1;

// "3-5,9": the frames that have windows, as --frames and render farms take them.
std::string frame_ranges(const std::vector<FrameCrops>& frames) {
    std::vector<int64_t> numbers;
    for (const FrameCrops& f : frames) numbers.push_back(f.frame);
    return format_frame_list(numbers);
}

}  // namespace

std::string crop_plan_to_json(const CropPlan& plan) {
    const double pixels = static_cast<double>(plan.width * plan.height * std::max<int64_t>(plan.frame_count, 1));
    std::string j = "{\n";
    j += "  \"format\": \"statfilter-crops\",\n  \"schema_version\": " + std::to_string(kCropsSchemaVersion) + ",\n";
    j += "  \"width\": " + std::to_string(plan.width) + ",\n  \"height\": " + std::to_string(plan.height) +
         ",\n  \"frame_count\": " + std::to_string(plan.frame_count) + ",\n";
    j += "  \"padding\": " + std::to_string(plan.options.padding) + ",\n  \"min_size\": " +
         std::to_string(plan.options.min_size) + ",\n  \"window_cost\": " + std::to_string(plan.options.window_cost) + ",\n";
    j += "  \"flagged_pixels\": " + std::to_string(plan.flagged()) + ",\n  \"flagged_fraction\": " +
         json_number(static_cast<double>(plan.flagged()) / pixels) + ",\n";
    j += "  \"window_count\": " + std::to_string(plan.window_count()) + ",\n  \"window_pixels\": " +
         std::to_string(plan.window_pixels()) + ",\n  \"window_fraction\": " +
         json_number(static_cast<double>(plan.window_pixels()) / pixels) + ",\n";
    j += "  \"cost_pixels\": " + std::to_string(plan.cost_pixels()) + ",\n";
    j += "  \"render_frames\": " + json_quote(frame_ranges(plan.frames)) + ",\n";
    j += "  \"frames\": [";
    for (size_t i = 0; i < plan.frames.size(); ++i) {
        const FrameCrops& f = plan.frames[i];
        j += (i ? ",\n" : "\n");
        int64_t frame_pixels = 0;
        for (const CropWindow& w : f.windows) frame_pixels += w.area();
        j += "    {\"frame\": " + std::to_string(f.frame) + ", \"flagged_pixels\": " + std::to_string(f.flagged) +
             ", \"window_count\": " + std::to_string(f.windows.size()) + ", \"window_pixels\": " +
             std::to_string(frame_pixels) + ", \"windows\": [";
        for (size_t k = 0; k < f.windows.size(); ++k) {
            const CropWindow& w = f.windows[k];
            // border: the same window as fractions of the frame, y up from the bottom edge (the
            // convention of Blender's render border, min_x, min_y, max_x, max_y).
            const double W = static_cast<double>(plan.width), H = static_cast<double>(plan.height);
            j += (k ? ",\n      " : "\n      ");
            j += "{\"index\": " + std::to_string(k) + ", \"x\": " + std::to_string(w.x) + ", \"y\": " + std::to_string(w.y) + ", \"width\": " +
                 std::to_string(w.width) + ", \"height\": " + std::to_string(w.height) + ", \"border\": [" +
                 json_number(w.x / W) + ", " + json_number(1.0 - (w.y + w.height) / H) + ", " +
                 json_number((w.x + w.width) / W) + ", " + json_number(1.0 - w.y / H) + "]}";
        }
        j += f.windows.empty() ? "]}" : "\n    ]}";
    }
    j += plan.frames.empty() ? "]\n}\n" : "\n  ]\n}\n";
    return j;
}

namespace {

[[noreturn]] void bad(const std::string& what) { throw Error(Status::InvalidArgument, "crops JSON: " + what); }

const JsonValue& member(const JsonValue& object, const std::string& key, const std::string& where) {
    const JsonValue* v = object.find(key);
    if (!v) bad(where + " has no \"" + key + "\"");
    return *v;
}

int64_t integer(const JsonValue& object, const std::string& key, const std::string& where, int64_t min_value) {
    const JsonValue& v = member(object, key, where);
    if (!v.is(JsonValue::Type::Number))
        bad(where + " \"" + key + "\" is " + JsonValue::type_name(v.type()) + ", not a number");
    const double d = v.number();
    if (std::floor(d) != d || std::fabs(d) > 9.0e15) bad(where + " \"" + key + "\" is " + json_number(d) + ", not an integer");
    if (d < static_cast<double>(min_value))
        bad(where + " \"" + key + "\" is " + json_number(d) + "; it must be >= " + std::to_string(min_value));
    return static_cast<int64_t>(d);
}

const std::vector<JsonValue>& array(const JsonValue& object, const std::string& key, const std::string& where) {
    const JsonValue& v = member(object, key, where);
    if (!v.is(JsonValue::Type::Array)) bad(where + " \"" + key + "\" is " + JsonValue::type_name(v.type()) + ", not an array");
    return v.array();
}

}  // namespace

CropPlan crop_plan_from_json(const std::string& text) {
    JsonValue root;
    try {
        root = parse_json(text);
    } catch (const Error& e) {
        bad(e.what());
    }
    if (!root.is(JsonValue::Type::Object)) bad("the document is " + std::string(JsonValue::type_name(root.type())) + ", not an object");
    const JsonValue* format = root.find("format");
    if (!format || !format->is(JsonValue::Type::String) || format->string() != "statfilter-crops")
        bad("\"format\" must be \"statfilter-crops\" (is this a crop-window file written by statfilter detect?)");
    // "version" is what files written before schema_version was named carry (the same schema 1).
    const char* version_key = root.find("schema_version") || !root.find("version") ? "schema_version" : "version";
    const int64_t version = integer(root, version_key, "the document", 1);
    if (version != kCropsSchemaVersion)
        bad("schema version " + std::to_string(version) + " is not supported (this statfilter reads version " +
            std::to_string(kCropsSchemaVersion) + ")");
    CropPlan plan;
    plan.width = integer(root, "width", "the document", 1);
    plan.height = integer(root, "height", "the document", 1);
    if (root.find("frame_count")) plan.frame_count = integer(root, "frame_count", "the document", 0);
    if (root.find("padding")) plan.options.padding = integer(root, "padding", "the document", 0);
    if (root.find("min_size")) plan.options.min_size = integer(root, "min_size", "the document", 1);
    if (root.find("window_cost")) plan.options.window_cost = integer(root, "window_cost", "the document", 0);
    std::set<int64_t> seen;
    for (const JsonValue& fv : array(root, "frames", "the document")) {
        if (!fv.is(JsonValue::Type::Object)) bad("an entry of \"frames\" is " + std::string(JsonValue::type_name(fv.type())) + ", not an object");
        FrameCrops f;
        f.frame = integer(fv, "frame", "a frame entry", std::numeric_limits<int64_t>::min() / 2);
        const std::string where = "frame " + std::to_string(f.frame);
        if (!seen.insert(f.frame).second) bad(where + " is listed twice");
        if (fv.find("flagged_pixels")) f.flagged = integer(fv, "flagged_pixels", where, 0);
        const auto& windows = array(fv, "windows", where);
        for (size_t k = 0; k < windows.size(); ++k) {
            const std::string wwhere = "window " + std::to_string(k) + " of " + where;
            if (!windows[k].is(JsonValue::Type::Object)) bad(wwhere + " is not an object");
            CropWindow w;
            w.x = integer(windows[k], "x", wwhere, 0);
            w.y = integer(windows[k], "y", wwhere, 0);
            w.width = integer(windows[k], "width", wwhere, 1);
            w.height = integer(windows[k], "height", wwhere, 1);
            if (w.x + w.width > plan.width)
                bad(wwhere + " (x " + std::to_string(w.x) + ", width " + std::to_string(w.width) +
                    ") extends past the image width " + std::to_string(plan.width));
            if (w.y + w.height > plan.height)
                bad(wwhere + " (y " + std::to_string(w.y) + ", height " + std::to_string(w.height) +
                    ") extends past the image height " + std::to_string(plan.height));
            f.windows.push_back(w);
        }
        if (!f.windows.empty()) plan.frames.push_back(std::move(f));
    }
    std::sort(plan.frames.begin(), plan.frames.end(), [](const FrameCrops& a, const FrameCrops& b) { return a.frame < b.frame; });
    return plan;
}

void check_crop_plan(const CropPlan& plan, int64_t width, int64_t height, const std::vector<int64_t>& frame_numbers) {
    if (plan.width != width || plan.height != height)
        throw Error(Status::InvalidArgument, "the crop windows are for " + std::to_string(plan.width) + " x " +
                                                 std::to_string(plan.height) + " frames; these are " +
                                                 std::to_string(width) + " x " + std::to_string(height));
    for (const FrameCrops& f : plan.frames)
        if (std::find(frame_numbers.begin(), frame_numbers.end(), f.frame) == frame_numbers.end())
            throw Error(Status::InvalidArgument, "the crop windows name frame " + std::to_string(f.frame) +
                                                     ", which the sequence does not have (frames " +
                                                     format_frame_list(frame_numbers) + ")");
}

}  // namespace statfilter
