// The core's errors as values, for the tests of the core (the C ABI tests see status codes instead).
#pragma once
#include <string>
#include <utility>

#include "statfilter/error.hpp"

namespace statfilter_test {

// The status and message read_sequence/write_sequence throw (Ok and "" when they do not).
template <class Body>
std::pair<statfilter::Status, std::string> error_of(Body&& body) {
    try {
        body();
    } catch (const statfilter::Error& e) {
        return {e.status(), e.what()};
    }
    return {statfilter::Status::Ok, ""};
}

}  // namespace statfilter_test
