#include "statfilter/filter.hpp"

#include "statfilter/error.hpp"

namespace statfilter {

void Filter::execute(const Sequence& input, Sequence& output, const Progress& progress) {
    if (input.shape() != output.shape())
        throw Error(Status::InvalidArgument, "output shape (" + to_string(output.shape()) +
                                                 ") differs from input shape (" + to_string(input.shape()) + ")");
    results_.clear();
    run(input, output, progress);
    if (&input != &output) output.copy_attributes_from(input);
}

}  // namespace statfilter
