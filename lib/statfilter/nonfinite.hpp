// What to do with NaN and Inf samples: refuse the input, or repair them and count.
#pragma once
#include <cstdint>
#include <string>

#include "statfilter/sequence.hpp"

namespace statfilter {

enum class NonFinitePolicy { Error, Repair };

NonFinitePolicy parse_nonfinite_policy(const std::string& name);

// Error: throws Error(Numeric) naming the first NaN/Inf (frame, pixel, channel). Repair: returns the count.
// first_row: the row of the whole frame that seq's row 0 is (seq may be a band of scanlines).
int64_t check_nonfinite(const Sequence& seq, NonFinitePolicy policy, int64_t first_row = 0);

// Replaces each series' non-finite samples (series j is tile[f * n + j] over f) by the mean of its
// finite samples, or 0 when it has none.
void repair_nonfinite(double* tile, int64_t frames, int64_t n);
// The same on a whole sequence in place: each (pixel, channel) series' non-finite samples become the
// mean of its finite samples, or 0.
void repair_sequence_nonfinite(Sequence& seq);

}  // namespace statfilter
