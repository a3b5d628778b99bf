// Factories of the built-in filters, listed by the registry.
#pragma once
#include <memory>

#include "statfilter/filter.hpp"

namespace statfilter {

std::unique_ptr<Filter> make_copy_filter();
std::unique_ptr<Filter> make_pca_filter();
std::unique_ptr<Filter> make_error_threshold_filter();
std::unique_ptr<Filter> make_moving_basis_filter();

}  // namespace statfilter
