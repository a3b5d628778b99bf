// What denoise and plan share: the method the options name, the filter's parameters from them, the
// run options (--memory, --threads, --overwrite).
#pragma once
#include <set>
#include <string>

#include <statfilter/statfilter.h>

#include "cli_args.hpp"
#include "cli_common.hpp"

namespace statfilter_cli {

extern const std::set<std::string> kRunOptions;
extern const char* const kRunHelp;

// --method, or auto for --quality, or the default (with --prefilter: the default's own).
std::string denoise_method(const Args& args);
// Every --name VALUE that is not a common option is a parameter of the filter.
void set_filter_parameters(FilterHandle& filter, const Args& args);
// --memory SIZE and --threads N into the run options (usage errors name the option).
sf_run_options run_options(const Args& args);
// --vectors PATTERN: the renderer's motion vectors (Cycles' Vector pass: X, Y, Z, W) as the filter's
// named input "vectors", files with the input's frames read beside it; a method that takes none is a
// usage error, before any work.
void set_vectors_input(FilterHandle& filter, const Args& args, const std::string& method);
extern const char* const kVectorsHelp;

}  // namespace statfilter_cli
