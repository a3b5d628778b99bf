// A plan's run: the name of the directory its tasks keep their files in, inside its work directory
// (task_common.hpp plan_files_dir), made from the plan's text and its input files.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace statfilter {

// The plan's text with its run named: "run": "run-" and 16 hex digits of a hash of the text and of
// `inputs` (what identifies the input files' contents: input_files_stamp), after its "work" line.
// The same request on the same, unchanged frames makes the same run (a task run again finds its
// files); other options, or frames rendered again, make another. Returns the run through `run`.
std::string name_plan_run(const std::string& text, const std::string& inputs, std::string* run);

// Each input frame's path, size and modification time (nanoseconds), for name_plan_run: a frame
// written again changes its run.
std::string input_files_stamp(const std::string& pattern, const std::vector<int64_t>& frame_numbers);

}  // namespace statfilter
