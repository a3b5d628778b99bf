#include "distributed/task_common.hpp"

#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>

#include "distributed/tile_files.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"

namespace statfilter {

namespace fs = std::filesystem;

// A task's frames are staged in a hidden directory beside the output frames (the same file system,
// so moving each into place is one atomic rename), named after the plan's files directory (its work
// directory and run) and task. Its full path is hashed in, so plans whose work directories share a
// name, or two runs in one, do not meet there (only the task that makes a staging directory reads
// it: the hash need not be stable).
std::string staging_dir(const JsonValue& plan, int64_t task) {
    return staging_dir(plan, task, plan.find("output")->string());
}

std::string staging_dir(const JsonValue& plan, int64_t task, const std::string& output_pattern) {
    const fs::path output(output_pattern);
    const std::string work = plan_files_dir(plan);  // the plan's run: two runs never share a staging name
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016zx", std::hash<std::string>()(work));
    return (output.parent_path() / ("." + fs::path(work).filename().string() + "-" + hash + ".frames-" +
                                    std::to_string(task))).string();
}

std::string staged_pattern(const std::string& staging, const std::string& output_pattern) {
    return staging + "/" + fs::path(output_pattern).filename().string();
}

void clear_staging(const std::string& staging) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    fs::create_directories(staging);
}

int64_t publish_staged(const std::string& staging, const std::string& output_pattern, const std::vector<int64_t>& numbers,
                       std::vector<std::string>& outputs) {
    const FramePattern staged(staged_pattern(staging, output_pattern)), final_pattern(output_pattern);
    int64_t bytes = 0;
    for (int64_t number : numbers) {
        std::error_code ec;
        fs::rename(staged.format(number), final_pattern.format(number), ec);
        if (ec) throw Error(Status::Io, "cannot rename into '" + final_pattern.format(number) + "': " + ec.message());
        outputs.push_back(final_pattern.format(number));
        bytes += static_cast<int64_t>(fs::file_size(final_pattern.format(number), ec));
    }
    fs::remove_all(staging);
    return bytes;
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
