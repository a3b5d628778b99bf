// What the subcommands share: RAII over C ABI handles, status checks, and the input/output options.
#pragma once
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <statfilter/statfilter.h>

#include "cli_args.hpp"
#include "cli_progress.hpp"

namespace statfilter_cli {

// A failure of the library, carrying its message.
struct Failure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Throws Failure with sf_last_error() unless status is SF_OK.
void check(sf_status status);

class SequenceHandle {
public:
    SequenceHandle() = default;
    ~SequenceHandle() { sf_sequence_release(handle_); }
    SequenceHandle(const SequenceHandle&) = delete;
    SequenceHandle& operator=(const SequenceHandle&) = delete;
    sf_sequence* out() { return &handle_; }
    sf_sequence get() const { return handle_; }
    sf_shape shape() const;
    std::string channel_name(int64_t c) const;

private:
    sf_sequence handle_ = nullptr;
};

class FilterHandle {
public:
    explicit FilterHandle(const std::string& name);
    ~FilterHandle() { sf_filter_release(handle_); }
    FilterHandle(const FilterHandle&) = delete;
    FilterHandle& operator=(const FilterHandle&) = delete;
    sf_filter get() const { return handle_; }
    void check(sf_status status) const;  // uses the filter's own message

private:
    sf_filter handle_ = nullptr;
};

// Options read by every command that reads a sequence.
extern const std::set<std::string> kInputOptions;
// Options read by every command that writes a sequence.
extern const std::set<std::string> kOutputOptions;
extern const char* const kInputHelp;
extern const char* const kOutputHelp;

// The read and write options the input and output flags ask for (the strings they point to live here).
class IoSettings {
public:
    explicit IoSettings(const Args& args);
    IoSettings(const IoSettings&) = delete;
    IoSettings& operator=(const IoSettings&) = delete;
    sf_read_options read;
    sf_write_options write;

private:
    std::string channels_, frames_, ocio_, in_cs_, work_cs_, out_cs_, compression_;
};

void read_input(const Args& args, const std::string& pattern, ProgressLine& progress, SequenceHandle& out);
// Sequences are written as EXR: any other extension is a usage error (checked by write_output; call
// it before the work too, so a typo fails at once).
void check_exr_output(const std::string& pattern);
void write_output(const Args& args, const SequenceHandle& seq, const std::string& pattern, ProgressLine& progress);

std::set<std::string> merged(std::initializer_list<std::set<std::string>> sets);
// Ascending frame numbers compactly, {1,2,3,5} -> "1-3,5". The CLI's one copy, used by every command:
// the library's (format_frame_list, lib/frame_pattern.cpp) is not in the C ABI the CLI is limited to.
std::string frame_list_text(const std::vector<int64_t>& frames);

}  // namespace statfilter_cli
