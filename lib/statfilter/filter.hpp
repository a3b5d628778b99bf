// A filter reads one sequence and writes another of the same shape, configured by named parameters.
#pragma once
#include <string>

#include "statfilter/params.hpp"
#include "statfilter/progress.hpp"
#include "statfilter/sequence.hpp"

namespace statfilter {

class Filter {
public:
    explicit Filter(std::vector<ParamSpec> params) : params_(std::move(params)) {}
    virtual ~Filter() = default;

    ParamSet& params() { return params_; }
    const ParamSet& params() const { return params_; }
    const Results& results() const { return results_; }

    // Checks shapes, runs the filter, and carries names, frame numbers and metadata to the output.
    void execute(const Sequence& input, Sequence& output, const Progress& progress);

protected:
    virtual void run(const Sequence& input, Sequence& output, const Progress& progress) = 0;
    Results& mutable_results() { return results_; }

private:
    ParamSet params_;
    Results results_;
};

}  // namespace statfilter
