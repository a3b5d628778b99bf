// Errors of the core: one exception type carrying the status the C ABI reports.
#pragma once
#include <stdexcept>
#include <string>

namespace statfilter {

enum class Status {
    Ok = 0,
    InvalidArgument = 1,
    OutOfMemory = 2,
    Io = 3,
    NotFound = 4,
    Unsupported = 5,
    Cancelled = 6,
    Numeric = 7,
    Internal = 8,
};

class Error : public std::runtime_error {
public:
    Error(Status status, const std::string& message) : std::runtime_error(message), status_(status) {}
    Status status() const { return status_; }

private:
    Status status_;
};

}  // namespace statfilter
