#include "distributed/task_common.hpp"

#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>

#include "distributed/tile_files.hpp"

namespace statfilter {

namespace fs = std::filesystem;

// A task's frames are staged in a hidden directory beside the output frames (the same file system,
// so moving each into place is one atomic rename), named after the plan's work directory and task.
// The work directory's full path is hashed in, so plans whose work directories share a name do not
// meet there (only the task that makes a staging directory reads it: the hash need not be stable).
std::string staging_dir(const JsonValue& plan, int64_t task) {
    const fs::path output(plan.find("output")->string());
    const std::string& work = plan.find("work")->string();
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016zx", std::hash<std::string>()(work));
    return (output.parent_path() / ("." + fs::path(work).filename().string() + "-" + hash + ".frames-" +
                                    std::to_string(task))).string();
}

std::string write_task_report(const std::string& path, int64_t index, const std::string& phase, double seconds,
                              double cpu, int threads, int64_t pixel_bytes_read, int64_t bytes_read,
                              int64_t bytes_written, const Results& results, const std::vector<std::string>& outputs) {
    std::ostringstream report;
    report << "{\"task\": " << index << ", \"phase\": " << json_quote(phase) << ", \"seconds\": " << json_number(seconds)
           << ", \"cpu_seconds\": " << json_number(cpu) << ", \"threads\": " << threads
           << ", \"pixel_bytes_read\": " << pixel_bytes_read << ", \"bytes_read\": " << bytes_read
           << ", \"bytes_written\": " << bytes_written << ", \"results\": " << results_json(results)
           << ", \"outputs\": [";
    for (size_t i = 0; i < outputs.size(); ++i) report << (i ? ", " : "") << json_quote(outputs[i]);
    report << "]}\n";
    const std::string text = report.str();
    write_file(path, text.data(), text.size());
    return text;
}

}  // namespace statfilter
