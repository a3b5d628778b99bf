#include "cli_progress.hpp"

#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>

namespace statfilter_cli {

namespace {

volatile std::sig_atomic_t g_signal = 0;

void on_signal(int signal) { g_signal = signal; }

}  // namespace

void install_interrupt_handlers() {
    struct sigaction action {};
    action.sa_handler = &on_signal;
    action.sa_flags = SA_RESETHAND;  // the second signal takes the default action: the process ends
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

int interrupted_by() { return g_signal; }

ProgressLine::ProgressLine(bool quiet) : quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0) {}

ProgressLine::~ProgressLine() { finish(); }

int ProgressLine::callback(void* user, double fraction, const char* stage) {
    static_cast<ProgressLine*>(user)->show(fraction, stage);
    return g_signal != 0 ? 1 : 0;
}

void ProgressLine::show(double fraction, const char* stage) {
    if (quiet_) return;
    const int percent = static_cast<int>(fraction * 100.0 + 0.5);
    const int step = tty_ ? percent : percent / 10;
    if (stage_ == stage && step == last_step_) return;
    if (stage_ != stage && open_line_ && tty_) std::fputc('\n', stderr);
    stage_ = stage;
    last_step_ = step;
    if (tty_) {
        std::fprintf(stderr, "\rstatfilter: %-10s %3d%%", stage, percent);
        open_line_ = true;
    } else {
        std::fprintf(stderr, "statfilter: %s %d%%\n", stage, percent);
    }
    std::fflush(stderr);
}

void ProgressLine::finish() {
    if (open_line_ && tty_) std::fputc('\n', stderr);
    open_line_ = false;
}

}  // namespace statfilter_cli
