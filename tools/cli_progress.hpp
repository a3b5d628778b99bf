// Progress on stderr: a rewritten line on a terminal, a line per 10% step in logs (render farms).
#pragma once
#include <string>

namespace statfilter_cli {

class ProgressLine {
public:
    explicit ProgressLine(bool quiet);
    ~ProgressLine();
    // Matches sf_progress_callback: user is the ProgressLine.
    static int callback(void* user, double fraction, const char* stage);
    void finish();

private:
    void show(double fraction, const char* stage);
    bool quiet_, tty_;
    std::string stage_;
    int last_step_ = -1;
    bool open_line_ = false;
};

}  // namespace statfilter_cli
