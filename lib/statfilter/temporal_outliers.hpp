// Fireflies: samples that are outliers in time, found before the temporal model sees them. A
// temporal basis spreads a single bright sample into every frame of its pixel (one 500 among values
// near 0.4 came out as 1.2-1.6 in all 32 frames); replacing it by its series' median keeps it out of
// the Gram and the projection, and its frame then gets the model's value there.
// A sample is an outlier when, in the transformed domain (PreparedSeries uses the log relative to the
// group's level for every transform: in linear units the skewed spread of a few samples per pixel
// has a tail that would be taken for fireflies, and its light lost), its magnitude exceeds its series' temporal
// median by more than z robust deviations (1.4826 x MAD over time, floored at the median deviation
// of all series so a constant series is not judged by zero); it is a firefly only when isolated in
// its frame: at most one of its 8 neighbours exceeds half that threshold. A light switching on moves
// every pixel's median or deviation, a moving object makes its neighbours outliers too: both stay.
// Where the image moves under the pixels a spike's neighbours are outliers in time too (so it is not
// alone) and its series' median is another surface's, so the same test is also made on the sample's
// residual above its neighbours (less the second brightest of its 8 in the frame), against that
// residual's temporal median and deviation, isolated among the residual scores: such a sample is
// replaced by its neighbours' median in its frame.
#pragma once
#include <cstdint>
#include <vector>

#include "statfilter/sequence.hpp"
#include "statfilter/time_series_tiles.hpp"
#include "statfilter/value_transform.hpp"

namespace statfilter {

// One replaced sample: frame, series index in the group's pixel-major order (pixel * channels +
// channel offset) and the value (linear domain) it is replaced by.
struct TemporalOutlier {
    int64_t frame = 0, series = 0;
    double value = 0;
};

struct OutlierOptions {
    ValueTransform transform = ValueTransform::Log;
    double scale = 1.0;            // the transform's scale
    double z = 0;                  // threshold in robust deviations; <= 0 finds nothing
    bool repair_nonfinite = false; // as the series will be (non-finite samples are never outliers)
    double budget_bytes = 512.0 * 1024 * 1024;
};

// The fireflies of channel group `group`, sorted by series then frame. The same for any budget.
std::vector<TemporalOutlier> find_temporal_outliers(const Sequence& seq, ChannelSelection group,
                                                    const OutlierOptions& options);

// Writes the replacements into seq's channels `group`: the samples the temporal model saw, for a
// stage that reads the sequence itself (e.g. an average along optical flow).
void replace_temporal_outliers(Sequence& seq, ChannelSelection group, const std::vector<TemporalOutlier>& outliers);

}  // namespace statfilter
