#include "pipeline/memory_budget.hpp"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>

#include "statfilter/error.hpp"

namespace statfilter {

int64_t parse_memory_size(const std::string& text) {
    size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    std::string unit = text.substr(used);
    for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();  // "6GB", "6GiB" read as "6G"
    if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
    double scale = 0;
    if (unit.empty() || unit == "B") scale = 1;
    else if (unit == "K") scale = 1024.0;
    else if (unit == "M") scale = 1024.0 * 1024;
    else if (unit == "G") scale = 1024.0 * 1024 * 1024;
    else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
    const double bytes = value * scale;
    if (used == 0 || scale == 0 || !std::isfinite(bytes) || bytes < 1 || bytes > 9.0e18)
        throw Error(Status::InvalidArgument, "memory size '" + text + "' is not a size such as 512M, 6G or 1.5G");
    return static_cast<int64_t>(bytes);
}

std::string format_bytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024 && u < 4) {
        bytes /= 1024;
        ++u;
    }
    char text[32];
    std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
    return text;
}

int64_t physical_memory_bytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? static_cast<int64_t>(pages) * size : int64_t{8} << 30;
}

int64_t default_memory_budget() { return physical_memory_bytes() / 2; }

void check_memory_budget(double needed, double budget, const std::string& what) {
    if (needed <= budget) return;
    // Round the smallest workable budget up to a size a user can type.
    const bool small = needed < 1024.0 * 1024.0;
    const double unit = small ? 1024.0 : 1024.0 * 1024.0;
    const double count = std::ceil(needed / unit);
    char suggestion[32];
    std::snprintf(suggestion, sizeof suggestion, small ? "%.0fK" : "%.0fM", count);
    throw Error(Status::OutOfMemory, what + " needs " + format_bytes(needed) + " but the memory budget is " +
                                         format_bytes(budget) + ": give at least --memory " + suggestion +
                                         " (memory parameter " + std::to_string(static_cast<int64_t>(count * unit)) +
                                         " bytes)");
}

}  // namespace statfilter
