// The subcommands of the statfilter CLI. Each returns the exit code; failures throw.
#pragma once

namespace statfilter_cli {

// The method `denoise` runs when none is given: the lowest error over the benchmark's scenes and
// levels (docs/benchmarks.md).
inline constexpr const char* kDefaultMethod = "error-threshold";
// With --prefilter (e.g. oidn) and no --method: the temporal pass that never raised the error over
// the prefilter alone, overall or where things move, on every scene and level (docs/oidn.md).
inline constexpr const char* kDefaultMethodWithPrefilter = "hybrid";

int cmd_info(int argc, char** argv);
int cmd_copy(int argc, char** argv);
int cmd_denoise(int argc, char** argv);
int cmd_compare(int argc, char** argv);
int cmd_plugins(int argc, char** argv);
int cmd_motion(int argc, char** argv);
int cmd_detect(int argc, char** argv);
int cmd_merge(int argc, char** argv);

}  // namespace statfilter_cli
