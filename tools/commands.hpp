// The subcommands of the statfilter CLI. Each returns the exit code; failures throw.
#pragma once

namespace statfilter_cli {

// The method `denoise` runs when none is given.
inline constexpr const char* kDefaultMethod = "pca";

int cmd_info(int argc, char** argv);
int cmd_copy(int argc, char** argv);
int cmd_denoise(int argc, char** argv);
int cmd_compare(int argc, char** argv);

}  // namespace statfilter_cli
