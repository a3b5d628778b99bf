// make_detect_plan: the detect filter's bands and phases, checked before anything runs.
#include "distributed/detect_plan.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "distributed/plan_json.hpp"
#include "filters/detect_filter.hpp"
#include "pipeline/memory_budget.hpp"
#include "statfilter/error.hpp"

namespace statfilter {

std::string make_detect_plan(const Filter& filter, const FrameSource& denoised, const FrameSource* noisy,
                             const DetectPlanRequest& request) {
    filter.check();
    if (request.mask.empty() && request.crops.empty() && request.score.empty() && request.degree_map.empty() &&
        request.preview.empty())
        throw Error(Status::InvalidArgument, "a detect plan writes the mask, the crop windows, the score, the degree map or its preview: give one");
    if (request.tiles < 0 || request.tile_rows < 0)
        throw Error(Status::InvalidArgument, "tiles and tile rows must be >= 0");
    if (request.tiles > 0 && request.tile_rows > 0)
        throw Error(Status::InvalidArgument, "give the number of tiles or the rows per tile, not both");
    const Shape& s = denoised.shape();
    const DetectOptions o = detect_options(filter.params(), noisy != nullptr);
    check_detect_options(s, noisy ? &noisy->shape() : nullptr, o);

    int64_t rows = request.tile_rows;
    if (request.tiles > 0) rows = (s.height + request.tiles - 1) / request.tiles;
    if (rows <= 0) rows = 256;
    rows = std::min(rows, s.height);
    const int64_t tiles = (s.height + rows - 1) / rows, halo = detect_halo(o);
    // A band task holds its rows and halo of every frame of both sequences, its mask and score rows,
    // the noise variance of its rows, and the regression's buffers (memory_mb, as the filter's).
    const int64_t held = std::min(s.height, rows + 2 * halo);
    const double inputs = 4.0 * static_cast<double>(s.frames * held * s.width * s.channels) * (noisy ? 2 : 1);
    const double outputs = 8.0 * static_cast<double>(s.frames * rows * s.width);
    const double variance = 8.0 * static_cast<double>(held * s.width * s.channels);
    const double regression = std::min(o.budget_bytes, 8.0 * 4.0 * static_cast<double>((s.frames + o.degree + 1) * rows * s.width * s.channels));
    const double budget = request.budget_bytes > 0 ? request.budget_bytes : static_cast<double>(default_memory_budget());
    check_memory_budget(inputs + outputs + variance + regression, budget,
                        "a detect band task (" + std::to_string(held) + " rows of every frame)");

    std::ostringstream tasks;
    int64_t index = 0;
    auto task = [&](const std::string& phase, const std::string& fields, const std::vector<int64_t>& after) {
        tasks << (index ? ",\n" : "") << "    {\"index\": " << index << ", \"phase\": " << json_quote(phase) << ", "
              << fields << ", \"after\": " << list_json(after) << "}";
        return index++;
    };
    auto band = [&](int64_t t) {
        const int64_t y0 = t * rows, y1 = std::min(s.height, y0 + rows);
        return "\"tile\": " + std::to_string(t) + ", \"rows\": " + range_json(y0, y1) + ", \"read_rows\": " +
               range_json(std::max<int64_t>(0, y0 - halo), std::min(s.height, y1 + halo));
    };
    std::vector<int64_t> noise, detect;
    for (int64_t t = 0; t < tiles; ++t) noise.push_back(task("noise", band(t), {}));
    const int64_t tolerance = task("tolerance", "\"tiles\": " + std::to_string(tiles), noise);
    for (int64_t t = 0; t < tiles; ++t) detect.push_back(task("detect", band(t), {tolerance}));
    task("masks", "\"frames\": " + range_json(0, s.frames), detect);

    const std::string reason = "detection is per pixel over time but for window averages reaching " +
                               std::to_string(halo) + " rows and the tolerance (the median relative noise of every pixel): " +
                               std::to_string(tiles) + " bands of " + std::to_string(rows) +
                               " rows, one tolerance task between two passes over them, one task writing the frames, maps and crop windows";
    std::ostringstream out;
    out << "{\n  \"format\": \"statfilter-plan\",\n  \"version\": " << request.version << ",\n";
    out << "  \"input\": " << json_quote(request.denoised) << ",\n  \"noisy\": " << json_quote(request.noisy) << ",\n";
    out << "  \"output\": " << json_quote(request.mask) << ",\n  \"crops\": " << json_quote(request.crops) << ",\n";
    out << "  \"score\": " << json_quote(request.score) << ",\n  \"degree_map\": " << json_quote(request.degree_map)
        << ",\n  \"preview\": " << json_quote(request.preview) << ",\n";
    out << "  \"work\": " << json_quote(request.work_dir) << ",\n";
    out << "  \"front_end\": " << (request.front_end.empty() ? "{}" : request.front_end) << ",\n";
    out << "  \"memory\": " << json_number(request.budget_bytes) << ",\n  \"threads\": " << request.threads << ",\n";
    out << "  \"shape\": {\"frames\": " << s.frames << ", \"height\": " << s.height << ", \"width\": " << s.width
        << ", \"channels\": " << s.channels << "},\n";
    out << "  \"frame_numbers\": " << list_json(denoised.attributes().frame_numbers()) << ",\n";
    out << "  \"kind\": \"detect\",\n  \"reason\": " << json_quote(reason) << ",\n";
    out << "  \"halo\": " << halo << ",\n  \"tile_rows\": " << rows << ",\n";
    out << "  \"tasks\": [\n" << tasks.str() << "\n  ]\n}\n";
    return out.str();
}

}  // namespace statfilter
