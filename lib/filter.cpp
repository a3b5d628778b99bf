#include "statfilter/filter.hpp"

#include "filters/prefilter.hpp"
#include "statfilter/error.hpp"

namespace statfilter {

namespace {

// A slice [start, start + span) of a parent's progress, as a Progress of its own.
Progress slice(const Progress& parent, double start, double span) {
    return Progress([&parent, start, span](double fraction, const char* stage) {
        parent.report(start + span * fraction, stage);  // throws when the parent cancels
        return true;
    });
}

}  // namespace

void Filter::execute(const Sequence& input, Sequence& output, const Progress& progress) {
    if (input.shape() != output.shape())
        throw Error(Status::InvalidArgument, "output shape (" + to_string(output.shape()) +
                                                 ") differs from input shape (" + to_string(input.shape()) + ")");
    results_.clear();
    // Filters with a prefilter parameter (the temporal ones) run on the prefilter's output.
    std::unique_ptr<Sequence> prefiltered;
    if (params_.has("prefilter") && !params_.get_string("prefilter").empty()) {
        prefiltered = run_prefilter(params_, input, slice(progress, 0, 0.5), results_);
        run(*prefiltered, output, slice(progress, 0.5, 0.5));
    } else {
        run(input, output, progress);
    }
    if (&input != &output) output.copy_attributes_from(input);
}

}  // namespace statfilter
