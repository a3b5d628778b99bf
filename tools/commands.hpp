// The subcommands of the statfilter CLI. Each returns the exit code; failures throw.
#pragma once

namespace statfilter_cli {

// The method `denoise` runs when none is given: auto at its default quality (balanced), on or near the
// benchmark's Pareto front on every scene and level (docs/benchmarks.md): global PCA on a still
// scene, the error threshold method where something moves.
inline constexpr const char* kDefaultMethod = "auto";
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
int cmd_report(int argc, char** argv);
int cmd_plan(int argc, char** argv);
int cmd_task(int argc, char** argv);

}  // namespace statfilter_cli
