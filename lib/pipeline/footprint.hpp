// What a stage reaches to produce one output frame, so a scheduler can stream it in bounded memory
// (and a distributed plan can cut it into tile tasks with the right halo).
#pragma once
#include <cstdint>
#include <string>

namespace statfilter {

enum class TemporalReach {
    Frame,   // this frame only (diffusion, single-frame plugins)
    Window,  // frames t - window_half .. t + window_half (motion compensation)
    Shot,    // the whole shot, through statistics summed over pixels (global PCA's Gram, light levels)
};

struct Footprint {
    TemporalReach reach = TemporalReach::Shot;
    int64_t window_half = 0;  // Window: frames on each side
    int64_t halo = 0;         // pixels beyond a tile the stage reads (diffusion iterations, pooling, flow search)
    int passes = 1;           // reads of its input (a statistics pass, then a reconstruction pass, ...)
    bool streams = false;     // false: the stage needs the whole shot in memory at once
};

std::string describe(const Footprint& footprint);

}  // namespace statfilter
