// Parameters every temporal filter shares, and the series preparation they imply.
#pragma once
#include <vector>

#include "statfilter/params.hpp"
#include "statfilter/temporal_basis.hpp"

namespace statfilter {

// transform, nonfinite, shared_basis, memory_mb, prefilter, prefilter_params.
std::vector<ParamSpec> temporal_common_params();

struct TemporalSetup {
    SeriesPrep prep;
    NonFinitePolicy nonfinite = NonFinitePolicy::Error;
    bool shared_basis = true;
    double budget_bytes = 0;
    int64_t nonfinite_samples = 0;  // NaN/Inf samples of the input, repaired in preparation (the second form)
};

TemporalSetup temporal_setup(const ParamSet& params);
// The preamble of a temporal filter's in-memory run: the setup, and the input checked against the
// nonfinite policy (error: throws naming the first NaN/Inf; repair: counts them).
TemporalSetup temporal_setup(const ParamSet& params, const Sequence& input);

// The channel groups that each get their own basis: all channels together, or one each.
std::vector<ChannelSelection> basis_groups(const Shape& shape, bool shared_basis);

// The rank parameter: "auto", "energy" or a count.
ParamSpec rank_param(const char* default_value);

}  // namespace statfilter

namespace statfilter {

// The 'energy' parameter used by rank=energy.
ParamSpec energy_param();

// The rank the parameters ask for, given a basis' eigenvalues; clamped to max_useful_rank.
RankChoice choose_rank(const ParamSet& params, const std::vector<double>& eigenvalues, int64_t series, int64_t frames);

}  // namespace statfilter
