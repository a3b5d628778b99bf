// Fuzz target: the command line as statfilter parses it. The bytes are split at NUL into argv and
// parsed with every command's flags and options (tools/cli_args.cpp); then the values the commands
// parse themselves go through the same parsers: patterns (positionals) and --frames. Usage errors
// are fine; a crash, a sanitizer report or a hang is a finding.
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "cli_args.hpp"
#include "statfilter/error.hpp"
#include "statfilter/frame_pattern.hpp"

namespace {

const std::set<std::string> kFlags = {"float", "clamp-half", "json", "quiet", "help"};
const std::set<std::string> kOptions = {"channels", "frames", "ocio", "in-colorspace", "working-colorspace",
                                        "compression", "out-colorspace", "method", "save", "crops", "mask",
                                        "feather", "noisy", "alpha", "beta"};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::vector<std::string> words(1, "statfilter");
    words.emplace_back();
    for (size_t i = 0; i < size; ++i) {
        if (data[i] == 0) words.emplace_back();
        else words.back() += static_cast<char>(data[i]);
    }
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    try {
        const statfilter_cli::Args args(static_cast<int>(words.size()), argv.data(), 2, kFlags, kOptions);
        for (const std::string& p : args.positionals()) {
            try {
                const statfilter::FramePattern pattern(p);
                for (int64_t frame : {int64_t{0}, int64_t{1}, int64_t{-7}, int64_t{123456789012345678}})
                    if (pattern.format(frame).empty()) __builtin_trap();
            } catch (const statfilter::Error&) {
            }
        }
        if (args.has("frames")) {
            try {
                statfilter::parse_frame_spec(args.option("frames"));
            } catch (const statfilter::Error&) {
            }
        }
    } catch (const statfilter_cli::UsageError&) {
    }
    return 0;
}
