// The hybrid's analysis (filters/hybrid_stage.hpp) as files, so that a plan's tasks can make its
// steps on other processes or nodes (WindowedStage's phases), each phase in a directory of its own:
//   the passes:     temporal.f32 (I_T, or a still scene's frames), grown.f32 (the moving weight),
//                   crossings.f32, change.bin (the change test's model), fireflies.bin, analysis.json;
//   a chunk of first passes: first.f32 (frames begin .. end - 1), first.json (their sums);
//   the guides:     guides.f32 and guides.json (their scale, the aligned average's light levels).
// Frames are float32, frame after frame, as the scratch held them. Nothing here is atomic: the
// caller writes a temporary directory and renames it into place.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "filters/hybrid_stage.hpp"
#include "pipeline/stage.hpp"
#include "statfilter/json.hpp"

namespace statfilter {

// extra_members: JSON object members ("key": value, ...) the caller reads back (may be empty).
void save_hybrid_passes(const HybridAnalysis& analysis, const Shape& shape, const std::string& dir,
                        const std::string& extra_members);
// The passes saved in dir; `json` (optional) receives analysis.json. Names the file that is missing
// or does not fit.
HybridAnalysis load_hybrid_passes(const Shape& shape, const Sequence& attributes, const TemporalChangeOptions& change,
                                  const std::string& dir, JsonValue* json);

// analysis.json of the passes saved in dir (the caller's own members with the rest).
JsonValue hybrid_passes_json(const std::string& dir);

// Frames [begin, end) of the first pass, written as they come (from several threads), then their sums.
class FirstPassFiles {
public:
    FirstPassFiles(const std::string& dir, const Shape& shape, int64_t begin, int64_t end);
    ~FirstPassFiles();
    FirstPassFiles(const FirstPassFiles&) = delete;
    FirstPassFiles& operator=(const FirstPassFiles&) = delete;
    void write(int64_t frame, const float* pixels);
    void finish(const HybridAnalysis& analysis);

private:
    std::string dir_;
    int64_t begin_, end_, frame_bytes_;
    int fd_ = -1;
};
// Every chunk's first passes (covering the shot): analysis.first_pass and its sums.
void load_first_passes(const Shape& shape, const Sequence& attributes, const std::vector<WindowedFiles::Chunk>& chunks,
                       HybridAnalysis& analysis);

void save_guides(const HybridAnalysis& analysis, const Shape& shape, const std::string& dir);
void load_guides(const Shape& shape, const Sequence& attributes, const std::string& dir, HybridAnalysis& analysis);

}  // namespace statfilter
