// Progress on stderr: a rewritten line on a terminal, a line per 10% step in logs (render farms).
#pragma once
#include <string>

namespace statfilter_cli {

// SIGINT and SIGTERM stop the work at the next progress report (the library then removes its
// temporary files and leaves the output as it was); a second signal ends the process at once.
void install_interrupt_handlers();
// The signal that interrupted the run, or 0.
int interrupted_by();

class ProgressLine {
public:
    explicit ProgressLine(bool quiet);
    ~ProgressLine();
    // Matches sf_progress_callback: user is the ProgressLine. Asks to cancel once interrupted.
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
