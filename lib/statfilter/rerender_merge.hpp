// Splicing re-rendered pixels back into a denoised sequence.
#pragma once
#include "statfilter/crop_windows.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

struct MergeOptions {
    const CropPlan* crops = nullptr;  // the re-rendered windows; null: the mask alone decides
    const Sequence* mask = nullptr;   // flagged pixels (non-zero in any channel); null: the windows decide
    int64_t feather = 0;              // pixels over which the replaced region's edge blends in
};

// output = denoised, with rerender's pixels spliced in, frame by frame (frames matched by frame
// number). The region replaced in a frame is the union of its crop windows, or the mask's pixels, or
// (both given) the mask's pixels, which must then lie inside the windows. With feather N > 0 the
// re-render's weight rises over the N pixels inside the region's edge: w = min(1, d / (N + 1)), d the
// distance to the nearest pixel outside the region (the image border is not an edge).
//
// rerender holds full-size frames (pixels outside the region are ignored, so a crop-window render
// pasted into a blank frame will do); it needs every frame that has a region, and no frame that the
// denoised sequence lacks. Throws Error(InvalidArgument) for mismatched sizes or channels, missing
// frames, an empty region (nothing to merge), or mask pixels outside the windows; Error(Numeric) for
// NaN/Inf in the re-rendered pixels used. Returns how many pixel-frames took re-rendered values.
int64_t merge_rerender(const Sequence& denoised, const Sequence& rerender, const MergeOptions& options, Sequence& output,
                    const Progress& progress);

}  // namespace statfilter
