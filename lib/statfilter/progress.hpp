// Progress reporting with cancellation: a callback that returns false stops the work.
#pragma once
#include <functional>

#include "statfilter/error.hpp"

namespace statfilter {

class Progress {
public:
    using Callback = std::function<bool(double fraction, const char* stage)>;

    Progress() = default;
    explicit Progress(Callback callback) : callback_(std::move(callback)) {}

    // Reports and throws Error(Cancelled) when the callback asks to stop.
    void report(double fraction, const char* stage) const {
        if (callback_ && !callback_(fraction, stage)) throw Error(Status::Cancelled, std::string("cancelled during ") + stage);
    }

private:
    Callback callback_;
};

}  // namespace statfilter

namespace statfilter {

// A slice [start, start + span) of a parent's progress, for one stage of a longer job.
struct ProgressSpan {
    const Progress& progress;
    double start = 0, span = 1;
    const char* stage = "";
    void report(double fraction) const { progress.report(start + span * fraction, stage); }
};

}  // namespace statfilter
