// What every task of a plan shares (lib/distributed/tile_tasks.cpp, detect_tasks.cpp): reading the
// task's JSON, counting the pixels it decodes, where its frames are staged, and its report.
#pragma once
#include <sys/resource.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/frame_source.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/json.hpp"

namespace statfilter {

inline const JsonValue& member(const JsonValue& object, const std::string& key, const std::string& where) {
    const JsonValue* v = object.find(key);
    if (!v) throw Error(Status::InvalidArgument, where + " has no '" + key + "'");
    return *v;
}
inline int64_t integer(const JsonValue& object, const std::string& key, const std::string& where) {
    return static_cast<int64_t>(member(object, key, where).number());
}
inline std::pair<int64_t, int64_t> range(const JsonValue& object, const std::string& key, const std::string& where) {
    const JsonValue& v = member(object, key, where);
    if (!v.is(JsonValue::Type::Array) || v.array().size() != 2)
        throw Error(Status::InvalidArgument, where + ": '" + key + "' is not a [begin, end) pair");
    return {static_cast<int64_t>(v.array()[0].number()), static_cast<int64_t>(v.array()[1].number())};
}

// Where a plan's tasks keep their files: the plan's work directory, then its run (a name made from
// the plan's own text when it was written): a plan made with other options or frames in the same
// work directory has another run, so none of its tasks ever reads an earlier plan's file. A plan
// without a run (written before runs were named) keeps them in the work directory itself.
inline std::string plan_files_dir(const JsonValue& plan) {
    const std::string& work = member(plan, "work", "the plan").string();
    const JsonValue* run = plan.find("run");
    return run ? work + "/" + run->string() : work;
}

inline double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Counts the bytes of pixels a task decodes from the shot (as float samples).
class CountingSource final : public FrameSource {
public:
    CountingSource(const FrameSource& base, std::atomic<int64_t>& bytes) : base_(base), bytes_(bytes) {}
    const Shape& shape() const override { return base_.shape(); }
    const Sequence& attributes() const override { return base_.attributes(); }
    void read_rows(int64_t f, int64_t y0, int64_t y1, float* dst) const override {
        base_.read_rows(f, y0, y1, dst);
        bytes_ += (y1 - y0) * base_.shape().width * base_.shape().channels * static_cast<int64_t>(sizeof(float));
    }

private:
    const FrameSource& base_;
    std::atomic<int64_t>& bytes_;
};

inline std::string results_json(const Results& r) {
    std::string s = "{";
    for (const std::string& name : r.names()) {
        bool number = true;
        double v = 0;
        try {
            v = r.get_float(name);
        } catch (const Error&) {
            number = false;
        }
        s += (s.size() > 1 ? ", " : "") + json_quote(name) + ": " + (number ? json_number(v) : json_quote(r.get_string(name)));
    }
    return s + "}";
}

// A string member that a plan may leave out (older plans): "" then.
inline std::string optional_text(const JsonValue& object, const std::string& key) {
    const JsonValue* v = object.find(key);
    return v && v->is(JsonValue::Type::String) ? v->string() : std::string();
}

// The task's frames are staged beside the plan's output pattern (or beside another pattern the task
// writes: a rename stays within its file system).
std::string staging_dir(const JsonValue& plan, int64_t task);
std::string staging_dir(const JsonValue& plan, int64_t task, const std::string& output_pattern);
// Where a task writes the frames of output_pattern first: staging/<the pattern's file name>.
std::string staged_pattern(const std::string& staging, const std::string& output_pattern);
// Makes the staging directory, empty (what a killed run of the task left there is removed).
void clear_staging(const std::string& staging);
// Moves each staged frame into its final name, one rename each, then removes the staging directory;
// appends the final names to outputs and returns the bytes moved.
int64_t publish_staged(const std::string& staging, const std::string& output_pattern, const std::vector<int64_t>& numbers,
                       std::vector<std::string>& outputs);

// Writes the task's report (JSON) last, atomically, at path; returns its text.
std::string write_task_report(const std::string& path, int64_t index, const std::string& phase, double seconds,
                              double cpu_seconds, int threads, int64_t pixel_bytes_read, int64_t bytes_read,
                              int64_t bytes_written, const Results& results, const std::vector<std::string>& outputs);

}  // namespace statfilter
