// The memory a run may use: sizes as users write them ("512M", "6G"), the default share of the
// machine, and the check that refuses a run before any work when it cannot fit.
#pragma once
#include <cstdint>
#include <string>

namespace statfilter {

// "512M", "6G", "1.5G", "800K", "2T", or a plain byte count. Throws Error(InvalidArgument).
int64_t parse_memory_size(const std::string& text);
// "1.5 GiB", "512 MiB", ...
std::string format_bytes(double bytes);

int64_t physical_memory_bytes();
// The budget used when the caller gives none: half of physical memory, so a render farm node keeps
// room for the renderer and the page cache (docs/architecture.md, "Memory").
int64_t default_memory_budget();

// Throws Error(OutOfMemory) naming what needs the memory, how much, the budget and the smallest
// budget that would do, when needed > budget.
void check_memory_budget(double needed_bytes, double budget_bytes, const std::string& what);

}  // namespace statfilter
