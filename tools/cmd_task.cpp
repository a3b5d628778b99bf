// statfilter task PLAN N: runs task N of a plan made by statfilter plan (what a farm's job runs).
#include <cstdio>
#include <cstdlib>

#include "cli_common.hpp"
#include "cli_progress.hpp"
#include "cli_run_setup.hpp"
#include "commands.hpp"

namespace statfilter_cli {

int cmd_task(int argc, char** argv) {
    const Args args(argc, argv, 2, {"help", "quiet", "overwrite"}, kRunOptions, {});
    if (args.flag("help")) {
        std::printf("usage: statfilter task PLAN N [--memory SIZE] [--threads N] [--quiet]\n\n"
                    "Runs task N (from 0) of a plan written by 'statfilter plan', after the tasks its \"after\"\n"
                    "list names. A task that died can be run again; a finished task run again rewrites the same\n"
                    "files. Its report (seconds, bytes read, results) goes to the plan's files in the work\n"
                    "directory (WORK/RUN/task-N.json, RUN the plan's \"run\").\n\n%s",
                    kRunHelp);
        return 0;
    }
    if (args.positionals().size() != 2) throw UsageError("expected PLAN and a task number N (see --help)");
    const std::string plan = args.positionals()[0], number = args.positionals()[1];
    char* end = nullptr;
    const long long task = std::strtoll(number.c_str(), &end, 10);
    if (number.empty() || *end != '\0' || task < 0) throw UsageError("the task number must be 0 or more, got '" + number + "'");
    sf_run_options run = run_options(args);
    if (run.overwrite) throw UsageError("--overwrite is not a task option: the plan says what it writes");
    ProgressLine progress(args.flag("quiet"));
    run.progress = &ProgressLine::callback;
    run.progress_user = &progress;
    check(sf_plan_run_task(plan.c_str(), task, &run));
    progress.finish();
    return 0;
}

}  // namespace statfilter_cli
