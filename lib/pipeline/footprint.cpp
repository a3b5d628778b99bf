#include "pipeline/footprint.hpp"

namespace statfilter {

std::string describe(const Footprint& f) {
    std::string reach = f.reach == TemporalReach::Frame    ? "this frame"
                        : f.reach == TemporalReach::Window ? "frames t-" + std::to_string(f.window_half) + "..t+" +
                                                                 std::to_string(f.window_half)
                                                           : "the whole shot";
    return reach + ", halo " + std::to_string(f.halo) + " px, " + std::to_string(f.passes) +
           (f.passes == 1 ? " pass" : " passes") + (f.streams ? ", streamed" : ", in memory");
}

}  // namespace statfilter
