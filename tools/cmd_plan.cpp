// statfilter plan IN OUT [denoise options] -o PLAN: the run as a plan of tasks for a render farm or
// any scheduler (statfilter task PLAN N runs one).
#include <cstdio>
#include <cstdlib>

#include "cli_common.hpp"
#include "cli_run_setup.hpp"
#include "commands.hpp"

namespace statfilter_cli {
namespace {

int64_t count_option(const Args& args, const char* name) {
    if (!args.has(name)) return 0;
    const std::string text = args.option(name);
    char* end = nullptr;
    const long long n = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || n <= 0) throw UsageError(std::string("--") + name + " takes a count above 0, got '" + text + "'");
    return n;
}

}  // namespace

int cmd_plan(int argc, char** argv) {
    const Args args(argc, argv, 2, {"help", "quiet", "float", "clamp-half"},
                    merged({kInputOptions, kOutputOptions, kRunOptions, {"method", "output-file", "tiles", "tile-rows", "frames-per-task", "work"}}));
    if (args.flag("help")) {
        std::printf("usage: statfilter plan IN OUT [denoise options] [--tiles N | --tile-rows R] -o PLAN\n\n"
                    "Writes the denoise run as a plan of tasks (JSON) that 'statfilter task PLAN N' runs one at a\n"
                    "time, on any node that sees IN, OUT and the work directory, in the order of each task's\n"
                    "'after' list. The output is the same as 'statfilter denoise IN OUT' with the same options\n"
                    "(docs/distributed.md). pca, error-threshold and --quality fast are cut into bands of rows\n"
                    "of every frame; per-frame methods into chunks of frames; other methods run as one task.\n\n"
                    "  -o PLAN, --output-file PLAN   the plan file to write\n"
                    "  --tiles N               bands of rows to cut the frames into (or --tile-rows R rows each;\n"
                    "                          default 256 rows)\n"
                    "  --frames-per-task N     frames per assembly or per-frame task (default 8)\n"
                    "  --work DIR              where tasks exchange files, on shared storage (default PLAN.work)\n"
                    "  --memory SIZE, --threads N   each task's (default: half of its node's memory, every core)\n"
                    "\n%s\n%s", kInputHelp, kOutputHelp);
        return 0;
    }
    if (args.positionals().size() != 2) throw UsageError("expected IN and OUT patterns (see --help)");
    if (!args.has("output-file")) throw UsageError("give the plan file to write: -o PLAN");
    if (args.has("tiles") && args.has("tile-rows")) throw UsageError("give --tiles or --tile-rows, not both");
    const std::string in = args.positionals()[0], out = args.positionals()[1], plan = args.option("output-file");
    check_exr_output(out);
    const std::string method = denoise_method(args);
    sf_run_options run = run_options(args);
    sf_plan_options options;
    sf_plan_options_init(&options);
    options.tiles = count_option(args, "tiles");
    options.tile_rows = count_option(args, "tile-rows");
    options.frames_per_task = count_option(args, "frames-per-task");
    const std::string work = args.option("work");
    options.work_dir = work.empty() ? nullptr : work.c_str();
    FilterHandle filter(method);
    set_filter_parameters(filter, args);
    IoSettings io(args);
    filter.check(sf_plan_write(filter.get(), in.c_str(), &io.read, out.c_str(), &io.write, &run, &options, plan.c_str()));
    int64_t count = 0;
    check(sf_plan_task_count(plan.c_str(), &count));
    if (!args.flag("quiet"))
        std::fprintf(stderr, "statfilter: %s: %lld tasks in %s; run each with 'statfilter task %s N' after the tasks "
                     "its \"after\" list names\n", method.c_str(), static_cast<long long>(count), plan.c_str(), plan.c_str());
    std::printf("%lld\n", static_cast<long long>(count));
    return 0;
}

}  // namespace statfilter_cli
