// Crop windows (cover the mask, little waste, JSON that round-trips and refuses bad files) and merge.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "statfilter/crop_windows.hpp"
#include "statfilter/error.hpp"
#include "statfilter/json.hpp"
#include "statfilter/rerender_merge.hpp"

using namespace statfilter;

namespace {

std::vector<uint8_t> blank(int64_t h, int64_t w) { return std::vector<uint8_t>(static_cast<size_t>(h * w), 0); }

void set(std::vector<uint8_t>& m, int64_t w, int64_t x, int64_t y) { m[static_cast<size_t>(y * w + x)] = 1; }

bool covered(const std::vector<CropWindow>& windows, int64_t x, int64_t y) {
    for (const auto& w : windows)
        if (x >= w.x && x < w.x + w.width && y >= w.y && y < w.y + w.height) return true;
    return false;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error";
    return "";
}

// A sequence filled with one value per frame and channel offset.
std::unique_ptr<Sequence> filled(const Shape& s, float base) {
    auto seq = std::make_unique<Sequence>(s);
    for (int64_t f = 0; f < s.frames; ++f)
        for (int64_t y = 0; y < s.height; ++y)
            for (int64_t x = 0; x < s.width; ++x)
                for (int64_t c = 0; c < s.channels; ++c) seq->at(f, y, x, c) = base + f + 0.1f * c;
    return seq;
}

}  // namespace

TEST(CropWindows, CoverEveryFlaggedPixelWithPaddingAndMinimumSize) {
    const int64_t H = 60, W = 80;
    auto m = blank(H, W);
    set(m, W, 10, 10);            // an isolated pixel
    for (int64_t x = 40; x < 50; ++x) set(m, W, x, 30);  // a short line
    set(m, W, 79, 59);            // the corner
    CropOptions o;
    o.padding = 2;
    o.min_size = 8;
    o.window_cost = 0;
    const auto windows = cover_mask(m, H, W, o);
    ASSERT_EQ(windows.size(), 3u);
    for (int64_t y = 0; y < H; ++y)
        for (int64_t x = 0; x < W; ++x)
            if (m[static_cast<size_t>(y * W + x)]) EXPECT_TRUE(covered(windows, x, y)) << x << "," << y;
    for (const auto& w : windows) {
        EXPECT_GE(w.x, 0);
        EXPECT_GE(w.y, 0);
        EXPECT_LE(w.x + w.width, W);
        EXPECT_LE(w.y + w.height, H);
        EXPECT_GE(w.width, 8);
        EXPECT_GE(w.height, 8);
    }
    // The line's window: padded by 2 on each side horizontally (14 wide), grown to 8 high.
    EXPECT_EQ(windows[1], (CropWindow{38, 27, 14, 8}));
    // The corner pixel: the window stays inside the image.
    EXPECT_EQ(windows[2], (CropWindow{72, 52, 8, 8}));
}

TEST(CropWindows, NearbyWindowsMergeWhenCheapOverlappingAlways) {
    const int64_t H = 40, W = 60;
    auto m = blank(H, W);
    set(m, W, 10, 10);
    set(m, W, 16, 10);  // 6 px apart: padded windows 5x5 at x 8..12 and 14..18
    set(m, W, 50, 35);
    CropOptions o;
    o.padding = 2;
    o.min_size = 1;
    o.window_cost = 0;
    EXPECT_EQ(cover_mask(m, H, W, o).size(), 3u);
    o.window_cost = 10;  // joining the two adds a 1 x 5 gap: 5 pixels
    const auto merged = cover_mask(m, H, W, o);
    ASSERT_EQ(merged.size(), 2u);
    EXPECT_EQ(merged[0], (CropWindow{8, 8, 11, 5}));
    // Windows grown to the minimum size overlap and are merged even with no budget.
    o.window_cost = 0;
    o.min_size = 12;
    const auto grown = cover_mask(m, H, W, o);
    EXPECT_EQ(grown.size(), 2u);
    for (size_t i = 0; i < grown.size(); ++i)
        for (size_t j = i + 1; j < grown.size(); ++j) {
            const auto& a = grown[i];
            const auto& b = grown[j];
            const bool disjoint = a.x + a.width <= b.x || b.x + b.width <= a.x || a.y + a.height <= b.y || b.y + b.height <= a.y;
            EXPECT_TRUE(disjoint);
        }
}

// The render cost (window_cost): two windows merge when the pixels their union adds cost at most one
// start-up (extra <= window_cost). Known answers below.
TEST(CropWindows, RenderCostWeighsStartUpAgainstExtraPixels) {
    const int64_t H = 40, W = 60;
    auto m = blank(H, W);
    set(m, W, 10, 10);
    set(m, W, 16, 10);
    set(m, W, 50, 35);
    CropOptions o;
    o.padding = 2;
    o.min_size = 1;
    const CropWindow left{8, 8, 5, 5}, right{14, 8, 5, 5}, far{48, 33, 5, 5}, pair{8, 8, 11, 5};
    // Cost 0: today's behaviour, nothing that does not overlap merges.
    o.window_cost = 0;
    EXPECT_EQ(cover_mask(m, H, W, o), (std::vector<CropWindow>{left, right, far}));
    // The nearby pair adds 5 pixels: a start-up worth 4 keeps them apart, one worth 5 merges them.
    o.window_cost = 4;
    EXPECT_EQ(cover_mask(m, H, W, o), (std::vector<CropWindow>{left, right, far}));
    o.window_cost = 5;
    EXPECT_EQ(cover_mask(m, H, W, o), (std::vector<CropWindow>{pair, far}));
    // The far window: the union of {8,8,11,5} and {48,33,5,5} is {8,8,45,30} = 1350 pixels, 1270 more
    // than the 55 + 25 the two cover; it stays apart below that cost and joins at it.
    o.window_cost = 1269;
    EXPECT_EQ(cover_mask(m, H, W, o), (std::vector<CropWindow>{pair, far}));
    o.window_cost = 1270;
    EXPECT_EQ(cover_mask(m, H, W, o), (std::vector<CropWindow>{CropWindow{8, 8, 45, 30}}));
}

// Cost 0 still merges windows whose union adds no pixel: grown to 4 x 4, the pixels at x 1 and 5
// give {0,1,4,4} and {4,1,4,4}, side by side; at x 1 and 6 a 1 x 4 gap (4 pixels) stays at cost 0.
TEST(CropWindows, RenderCostZeroMergesOnlyWhatCostsNothing) {
    const int64_t H = 10, W = 12;
    CropOptions o;
    o.padding = 0;
    o.min_size = 4;
    o.window_cost = 0;
    auto touching = blank(H, W);
    set(touching, W, 1, 2);
    set(touching, W, 5, 2);
    EXPECT_EQ(cover_mask(touching, H, W, o), (std::vector<CropWindow>{CropWindow{0, 1, 8, 4}}));
    auto gap = blank(H, W);
    set(gap, W, 1, 2);
    set(gap, W, 6, 2);
    EXPECT_EQ(cover_mask(gap, H, W, o), (std::vector<CropWindow>{CropWindow{0, 1, 4, 4}, CropWindow{5, 1, 4, 4}}));
    o.window_cost = 3;
    EXPECT_EQ(cover_mask(gap, H, W, o).size(), 2u);
    o.window_cost = 4;
    EXPECT_EQ(cover_mask(gap, H, W, o), (std::vector<CropWindow>{CropWindow{0, 1, 9, 4}}));
}

// Each merge saves one start-up for at most as many pixels, so the plan's cost (pixels + windows x
// cost) at a render cost is never above that of the unmerged windows (cost 0) counted at it.
TEST(CropWindows, MergingNeverRaisesThePlansCost) {
    const int64_t H = 48, W = 64;
    uint32_t state = 12345;
    auto next = [&state] { return state = state * 1664525u + 1013904223u; };
    for (int trial = 0; trial < 20; ++trial) {
        auto m = blank(H, W);
        for (int k = 0; k < 12; ++k) set(m, W, (next() >> 8) % W, (next() >> 8) % H);
        for (int64_t cost : {0, 3, 17, 64, 300, 5000}) {
            CropOptions o;
            o.padding = 1;
            o.min_size = 2;
            o.window_cost = 0;
            const auto apart = cover_mask(m, H, W, o);
            o.window_cost = cost;
            const auto merged = cover_mask(m, H, W, o);
            auto plan_cost = [cost](const std::vector<CropWindow>& ws) {
                int64_t c = 0;
                for (const auto& w : ws) c += w.area() + cost;
                return c;
            };
            EXPECT_LE(plan_cost(merged), plan_cost(apart)) << "trial " << trial << " cost " << cost;
            EXPECT_LE(merged.size(), apart.size());
            for (int64_t y = 0; y < H; ++y)
                for (int64_t x = 0; x < W; ++x)
                    if (m[static_cast<size_t>(y * W + x)]) ASSERT_TRUE(covered(merged, x, y));
        }
    }
}

TEST(CropWindows, ManyScatteredPixelsStayCoveredAndFast) {
    const int64_t H = 300, W = 400;
    auto m = blank(H, W);
    for (int64_t i = 0; i < 4000; ++i) set(m, W, (i * 7919) % W, (i * 104729) % H);
    const auto windows = cover_mask(m, H, W, CropOptions{});
    for (int64_t y = 0; y < H; ++y)
        for (int64_t x = 0; x < W; ++x)
            if (m[static_cast<size_t>(y * W + x)]) ASSERT_TRUE(covered(windows, x, y));
    EXPECT_LE(windows.size(), 512u);
}

TEST(CropWindows, EmptyMaskGivesNoWindows) {
    EXPECT_TRUE(cover_mask(blank(10, 10), 10, 10, CropOptions{}).empty());
    Sequence mask(Shape{3, 10, 10, 1});
    const CropPlan plan = make_crop_plan(mask, CropOptions{});
    EXPECT_TRUE(plan.frames.empty());
    EXPECT_EQ(plan.window_count(), 0);
    const CropPlan back = crop_plan_from_json(crop_plan_to_json(plan));
    EXPECT_TRUE(back.frames.empty());
}

TEST(CropWindows, JsonRoundTrips) {
    Sequence mask(Shape{4, 30, 50, 1});
    mask.frame_numbers() = {101, 102, 103, 104};
    mask.at(0, 5, 5, 0) = 1;
    mask.at(2, 20, 40, 0) = 1;
    mask.at(2, 21, 41, 0) = 1;
    mask.at(2, 2, 45, 0) = 1;
    const CropPlan plan = make_crop_plan(mask, CropOptions{});
    const std::string json = crop_plan_to_json(plan);
    const CropPlan back = crop_plan_from_json(json);
    EXPECT_EQ(back.width, 50);
    EXPECT_EQ(back.height, 30);
    EXPECT_EQ(back.frame_count, 4);
    ASSERT_EQ(back.frames.size(), plan.frames.size());
    for (size_t i = 0; i < plan.frames.size(); ++i) {
        EXPECT_EQ(back.frames[i].frame, plan.frames[i].frame);
        EXPECT_EQ(back.frames[i].flagged, plan.frames[i].flagged);
        EXPECT_EQ(back.frames[i].windows, plan.frames[i].windows);
    }
    EXPECT_EQ(back.frames[0].frame, 101);
    EXPECT_EQ(back.frames[1].frame, 103);
    EXPECT_EQ(crop_plan_to_json(back), json);
    // The normalised border (y up) of the first window.
    const JsonValue doc = parse_json(json);
    const JsonValue& w = doc.find("frames")->array()[0].find("windows")->array()[0];
    const CropWindow& cw = plan.frames[0].windows[0];
    EXPECT_NEAR(w.find("border")->array()[1].number(), 1.0 - (cw.y + cw.height) / 30.0, 1e-9);
    // What a farm reads per frame and window: the window's index ({window} of merge's file names),
    // the frame's window count and pixels, and the plan's cost in pixels.
    const JsonValue& f2 = doc.find("frames")->array()[1];
    const auto& ws = f2.find("windows")->array();
    ASSERT_EQ(ws.size(), plan.frames[1].windows.size());
    int64_t pixels = 0;
    for (size_t k = 0; k < ws.size(); ++k) {
        EXPECT_EQ(ws[k].find("index")->number(), static_cast<double>(k));
        pixels += plan.frames[1].windows[k].area();
    }
    EXPECT_EQ(f2.find("window_count")->number(), static_cast<double>(ws.size()));
    EXPECT_EQ(f2.find("window_pixels")->number(), static_cast<double>(pixels));
    EXPECT_EQ(doc.find("cost_pixels")->number(), static_cast<double>(plan.window_pixels() + 64 * plan.window_count()));
}

TEST(CropWindows, MalformedOrOutOfBoundsJsonIsRefusedWithTheReason) {
    const std::string head = R"({"format": "statfilter-crops", "version": 1, "width": 50, "height": 30, "frames": )";
    EXPECT_NE(error_of([] { crop_plan_from_json("{\"format\": \"statfilter-crops\", "); }).find("malformed JSON at line 1"),
              std::string::npos);
    EXPECT_NE(error_of([] { crop_plan_from_json("[1, 2]"); }).find("not an object"), std::string::npos);
    EXPECT_NE(error_of([] { crop_plan_from_json(R"({"version": 1})"); }).find("\"format\""), std::string::npos);
    EXPECT_NE(error_of([&] {
                  crop_plan_from_json(R"({"format": "statfilter-crops", "version": 2, "width": 5, "height": 5, "frames": []})");
              }).find("version 2"),
              std::string::npos);
    EXPECT_NE(error_of([&] { crop_plan_from_json(head + R"([{"frame": 3, "windows": [{"x": 45, "y": 0, "width": 10, "height": 4}]}]})"); })
                  .find("window 0 of frame 3 (x 45, width 10) extends past the image width 50"),
              std::string::npos);
    EXPECT_NE(error_of([&] { crop_plan_from_json(head + R"([{"frame": 3, "windows": [{"x": 0, "y": 28, "width": 1, "height": 4}]}]})"); })
                  .find("past the image height 30"),
              std::string::npos);
    EXPECT_NE(error_of([&] { crop_plan_from_json(head + R"([{"frame": 3, "windows": [{"x": -1, "y": 0, "width": 1, "height": 1}]}]})"); })
                  .find("must be >= 0"),
              std::string::npos);
    EXPECT_NE(error_of([&] { crop_plan_from_json(head + R"([{"frame": 3, "windows": [{"x": 1.5, "y": 0, "width": 1, "height": 1}]}]})"); })
                  .find("not an integer"),
              std::string::npos);
    EXPECT_NE(error_of([&] { crop_plan_from_json(head + R"([{"frame": 3, "windows": [{"x": 1, "y": 0, "height": 1}]}]})"); })
                  .find("has no \"width\""),
              std::string::npos);
    EXPECT_NE(error_of([&] { crop_plan_from_json(head + R"([{"frame": 3, "windows": []}, {"frame": 3, "windows": []}]})"); })
                  .find("frame 3 is listed twice"),
              std::string::npos);
    EXPECT_NE(error_of([&] { crop_plan_from_json(head + R"("none"})"); }).find("not an array"), std::string::npos);
}

TEST(Merge, SplicesWindowsAndLeavesEverythingElse) {
    const Shape s{3, 20, 30, 2};
    auto den = filled(s, 0.0f);
    auto rr = filled(s, 100.0f);
    CropPlan plan;
    plan.width = 30;
    plan.height = 20;
    plan.frame_count = 3;
    plan.frames.push_back({2, 1, {{5, 6, 4, 3}, {20, 0, 10, 20}}});
    Sequence out(s);
    MergeOptions o;
    o.crops = &plan;
    const int64_t n = merge_rerender(*den, *rr, o, out, Progress());
    EXPECT_EQ(n, 4 * 3 + 10 * 20);
    for (int64_t f = 0; f < 3; ++f)
        for (int64_t y = 0; y < 20; ++y)
            for (int64_t x = 0; x < 30; ++x) {
                const bool inside = f == 1 && ((x >= 5 && x < 9 && y >= 6 && y < 9) || x >= 20);
                for (int64_t c = 0; c < 2; ++c)
                    ASSERT_EQ(out.at(f, y, x, c), inside ? rr->at(f, y, x, c) : den->at(f, y, x, c));
            }
}

// Any feather is a weight: the largest (UBSan: no signed overflow) gives the re-render almost none.
TEST(Merge, HugeFeatherIsAWeightNotAnOverflow) {
    const Shape s{1, 20, 20, 1};
    auto den = filled(s, 0.0f);
    auto rr = filled(s, 1.0f);
    Sequence mask(Shape{1, 20, 20, 1});
    for (int64_t y = 5; y < 15; ++y)
        for (int64_t x = 5; x < 15; ++x) mask.at(0, y, x, 0) = 1;
    Sequence out(s);
    MergeOptions o;
    o.mask = &mask;
    o.feather = std::numeric_limits<int64_t>::max();
    EXPECT_EQ(merge_rerender(*den, *rr, o, out, Progress()), 100);
    EXPECT_EQ(out.at(0, 4, 10, 0), 0.0f);
    EXPECT_GT(out.at(0, 10, 10, 0), 0.0f);
    EXPECT_LT(out.at(0, 10, 10, 0), 1e-12f);
}

TEST(Merge, MaskRestrictsAndFeatherBlendsInsideTheEdge) {
    const Shape s{1, 20, 20, 1};
    auto den = filled(s, 0.0f);
    auto rr = filled(s, 1.0f);
    Sequence mask(Shape{1, 20, 20, 1});
    for (int64_t y = 5; y < 15; ++y)
        for (int64_t x = 5; x < 15; ++x) mask.at(0, y, x, 0) = 1;
    Sequence out(s);
    MergeOptions o;
    o.mask = &mask;
    o.feather = 2;
    merge_rerender(*den, *rr, o, out, Progress());
    EXPECT_EQ(out.at(0, 4, 10, 0), 0.0f);                  // outside
    EXPECT_NEAR(out.at(0, 5, 10, 0), 1.0f / 3, 1e-6);      // edge pixel: distance 1 of feather 2
    EXPECT_NEAR(out.at(0, 6, 10, 0), 2.0f / 3, 1e-6);
    EXPECT_EQ(out.at(0, 10, 10, 0), 1.0f);                 // deep inside: all re-render
    // The image border is not an edge: a region touching it is not feathered there.
    Sequence all(Shape{1, 20, 20, 1});
    for (int64_t y = 0; y < 20; ++y)
        for (int64_t x = 0; x < 20; ++x) all.at(0, y, x, 0) = 1;
    o.mask = &all;
    merge_rerender(*den, *rr, o, out, Progress());
    EXPECT_EQ(out.at(0, 0, 0, 0), 1.0f);
    // Mask and windows: only the mask's pixels, and they must lie inside the windows.
    CropPlan plan;
    plan.width = plan.height = 20;
    plan.frames.push_back({1, 0, {{0, 0, 12, 12}}});
    o.mask = &mask;
    o.crops = &plan;
    o.feather = 0;
    EXPECT_NE(error_of([&] { merge_rerender(*den, *rr, o, out, Progress()); }).find("outside its crop windows"),
              std::string::npos);
    plan.frames[0].windows[0] = {4, 4, 12, 12};
    merge_rerender(*den, *rr, o, out, Progress());
    EXPECT_EQ(out.at(0, 4, 4, 0), 0.0f);  // window, not mask
    EXPECT_EQ(out.at(0, 5, 5, 0), 1.0f);
}

TEST(Merge, RerenderFramesAreMatchedByNumber) {
    const Shape s{4, 8, 8, 1};
    auto den = filled(s, 0.0f);
    den->frame_numbers() = {10, 11, 12, 13};
    auto rr = filled(Shape{1, 8, 8, 1}, 50.0f);
    rr->frame_numbers() = {12};
    CropPlan plan;
    plan.width = plan.height = 8;
    plan.frames.push_back({12, 0, {{0, 0, 2, 2}}});
    Sequence out(s);
    MergeOptions o;
    o.crops = &plan;
    merge_rerender(*den, *rr, o, out, Progress());
    EXPECT_EQ(out.at(2, 0, 0, 0), 50.0f);
    EXPECT_EQ(out.at(2, 3, 3, 0), den->at(2, 3, 3, 0));
    // A frame with windows but no re-render.
    plan.frames.push_back({13, 0, {{0, 0, 2, 2}}});
    EXPECT_NE(error_of([&] { merge_rerender(*den, *rr, o, out, Progress()); }).find("re-render has no frame 13"),
              std::string::npos);
}

TEST(Merge, BadInputIsRefusedBeforeAnythingIsWritten) {
    const Shape s{2, 8, 8, 3};
    auto den = filled(s, 0.0f);
    Sequence out(s);
    CropPlan plan;
    plan.width = plan.height = 8;
    plan.frames.push_back({1, 0, {{0, 0, 2, 2}}});
    MergeOptions o;
    o.crops = &plan;
    auto small = filled(Shape{2, 8, 7, 3}, 1.0f);
    EXPECT_NE(error_of([&] { merge_rerender(*den, *small, o, out, Progress()); }).find("re-rendered frames are 7 x 8"),
              std::string::npos);
    auto gray = filled(Shape{2, 8, 8, 1}, 1.0f);
    EXPECT_NE(error_of([&] { merge_rerender(*den, *gray, o, out, Progress()); }).find("1 channels"), std::string::npos);
    auto rr = filled(s, 1.0f);
    CropPlan wrong = plan;
    wrong.width = 9;
    o.crops = &wrong;
    EXPECT_NE(error_of([&] { merge_rerender(*den, *rr, o, out, Progress()); }).find("are for 9 x 8 frames"), std::string::npos);
    CropPlan other = plan;
    other.frames[0].frame = 7;
    o.crops = &other;
    EXPECT_NE(error_of([&] { merge_rerender(*den, *rr, o, out, Progress()); }).find("name frame 7"), std::string::npos);
    CropPlan none = plan;
    none.frames.clear();
    o.crops = &none;
    EXPECT_NE(error_of([&] { merge_rerender(*den, *rr, o, out, Progress()); }).find("nothing to merge"), std::string::npos);
    Sequence empty_mask(Shape{2, 8, 8, 1});
    o.crops = nullptr;
    o.mask = &empty_mask;
    EXPECT_NE(error_of([&] { merge_rerender(*den, *rr, o, out, Progress()); }).find("the mask flags no pixel"),
              std::string::npos);
    o.mask = nullptr;
    EXPECT_NE(error_of([&] { merge_rerender(*den, *rr, o, out, Progress()); }).find("needs the crop windows, a mask"),
              std::string::npos);
    // Nothing was written on any failure.
    for (int64_t y = 0; y < 8; ++y) EXPECT_EQ(out.at(0, y, 0, 1), 0.0f);  // the denoised value would be 0.1
    // NaN in the re-rendered pixels used.
    o.crops = &plan;
    rr->at(0, 1, 1, 2) = std::nanf("");
    try {
        merge_rerender(*den, *rr, o, out, Progress());
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Numeric);
    }
}
