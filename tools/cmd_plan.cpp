// statfilter plan IN OUT [denoise options] -o PLAN: the run as a plan of tasks for a render farm or
// any scheduler (statfilter task PLAN N runs one).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>
#include <cstdlib>

#include "cli_common.hpp"
#include "cli_images.hpp"
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

std::string dashes_to_underscores(std::string s) {
    std::replace(s.begin(), s.end(), '-', '_');
    return s;
}

// statfilter plan detect DENOISED --noisy NOISY [--mask M] [--crops C] [--score S] [--degree-map D]
// [--preview P] [detect parameters] -o PLAN:
// `statfilter detect` as a plan, read the same way with `plan` in front.
int plan_detect(int argc, char** argv) {
    const Args args(argc, argv, 3, {"help", "quiet"},
                    merged({kInputOptions, kRunOptions, {"noisy", "mask", "crops", "score", "degree-map", "preview", "output-file", "tiles", "tile-rows", "work"}}),
                    filter_parameter_names("detect"));
    if (args.flag("help")) {
        std::printf("usage: statfilter plan detect DENOISED --noisy NOISY [--mask M.####.exr] [--crops C.json]\n"
                    "                      [--score S.####.exr] [--degree-map D.exr] [--preview D.png]\n"
                    "                      [detect parameters] [--tiles N | --tile-rows R] -o PLAN\n\n"
                    "Writes 'statfilter detect' as a plan of tasks (JSON) that 'statfilter task PLAN N' runs one at\n"
                    "a time, in the order of each task's 'after' list: noise tasks per band of rows, one tolerance\n"
                    "task, detect tasks per band, one task writing the frames, maps and crop windows. Each is the\n"
                    "same as 'statfilter detect' writes with the same options (docs/distributed.md).\n\n"
                    "  --noisy PATTERN         the noisy render DENOISED was made from\n"
                    "  --mask PATTERN          write the mask, one EXR per frame\n"
                    "  --crops PATH            write the crop windows as JSON\n"
                    "  --score PATTERN         write the estimated relMSE of each pixel-frame (float EXR per frame)\n"
                    "  --degree-map PATH       write the degree map, one float EXR\n"
                    "  --preview PATH.png      false-colour preview of the degree map (at least one output is given)\n"
                    "  -o PLAN, --output-file PLAN   the plan file to write\n"
                    "  --tiles N               bands of rows (or --tile-rows R rows each; default 256 rows)\n"
                    "  --work DIR              where tasks exchange files, on shared storage (default PLAN.work)\n"
                    "  --memory SIZE, --threads N   each task's (default: half of its node's memory, every core)\n"
                    "  detect parameters       as 'statfilter detect --help' lists them (--degree, --threshold, ...)\n"
                    "\n%s", kInputHelp);
        return 0;
    }
    if (args.positionals().size() != 1) throw UsageError("plan detect takes one DENOISED pattern (see --help)");
    if (!args.has("output-file")) throw UsageError("give the plan file to write: -o PLAN");
    if (!args.has("mask") && !args.has("crops") && !args.has("score") && !args.has("degree-map") && !args.has("preview"))
        throw UsageError("give what the plan writes: --mask PATTERN, --crops PATH, --score PATTERN, --degree-map PATH or --preview PATH");
    if (args.has("tiles") && args.has("tile-rows")) throw UsageError("give --tiles or --tile-rows, not both");
    for (const char* frames : {"mask", "score"})
        if (args.has(frames)) check_exr_output(args.option(frames));
    const std::string in = args.positionals()[0], plan = args.option("output-file");
    sf_run_options run = run_options(args);
    sf_plan_options options;
    sf_plan_options_init(&options);
    options.tiles = count_option(args, "tiles");
    options.tile_rows = count_option(args, "tile-rows");
    const std::string work = args.option("work"), noisy = args.option("noisy");
    options.work_dir = work.empty() ? nullptr : work.c_str();
    const std::string mask = args.option("mask"), crops = args.option("crops"), score = args.option("score"),
                      degree_map = args.option("degree-map"), preview = args.option("preview");
    auto given = [](const std::string& s) { return s.empty() ? nullptr : s.c_str(); };
    sf_detect_outputs outputs;
    sf_detect_outputs_init(&outputs);
    outputs.mask = given(mask);
    outputs.crops = given(crops);
    outputs.score = given(score);
    outputs.degree_map = given(degree_map);
    outputs.preview = given(preview);
    FilterHandle filter("detect");
    for (const auto& [name, value] : args.extras())
        filter.check(sf_filter_set_string(filter.get(), dashes_to_underscores(name).c_str(), value.c_str()));
    IoSettings io(args);
    filter.check(sf_plan_write_detect_outputs(filter.get(), in.c_str(), given(noisy), &io.read, &outputs, &run, &options,
                                              plan.c_str()));
    int64_t count = 0;
    check(sf_plan_task_count(plan.c_str(), &count));
    if (!args.flag("quiet"))
        std::fprintf(stderr, "statfilter: detect: %lld tasks in %s; run each with 'statfilter task %s N' after the tasks "
                     "its \"after\" list names\n", static_cast<long long>(count), plan.c_str(), plan.c_str());
    std::printf("%lld\n", static_cast<long long>(count));
    return 0;
}

}  // namespace

int cmd_plan(int argc, char** argv) {
    if (argc > 2 && std::string(argv[2]) == "detect") return plan_detect(argc, argv);
    const Args args(argc, argv, 2, {"help", "quiet", "float", "clamp-half"},
                    merged({kInputOptions, kOutputOptions, kRunOptions, {"method", "output-file", "tiles", "tile-rows", "frames-per-task", "work", "save", "vectors"}}));
    if (args.flag("help")) {
        std::printf("usage: statfilter plan IN OUT [denoise options] [--tiles N | --tile-rows R] -o PLAN\n"
                    "       statfilter plan detect DENOISED --noisy NOISY [--mask M] [--crops C] [...] -o PLAN\n"
                    "                                        (statfilter plan detect --help)\n\n"
                    "Writes the denoise run as a plan of tasks (JSON) that 'statfilter task PLAN N' runs one at a\n"
                    "time, on any node that sees IN, OUT and the work directory, in the order of each task's\n"
                    "'after' list. The output is the same as 'statfilter denoise IN OUT' with the same options\n"
                    "(docs/distributed.md). pca, error-threshold, moving-basis and --quality fast are cut into\n"
                    "bands of rows of every frame; --quality balanced and the hybrid into one analysis task,\n"
                    "then chunks of frames; per-frame methods into chunks of frames; other methods run as one\n"
                    "task.\n\n"
                    "  -o PLAN, --output-file PLAN   the plan file to write\n"
                    "  --tiles N               bands of rows to cut the frames into (or --tile-rows R rows each;\n"
                    "                          default 256 rows)\n"
                    "  --frames-per-task N     frames per assembly, window or per-frame task (default 8)\n"
                    "  --work DIR              where tasks exchange files, on shared storage (default PLAN.work)\n"
                    "  --save NAME=PATH[,...]  image results, as denoise writes them: rank_map (error-threshold),\n"
                    "                          alpha (balanced, hybrid), or any of a one-task plan's (PNG: false colour)\n"
                    "  --memory SIZE, --threads N   each task's (default: half of its node's memory, every core)\n"
                    "%s\n%s\n%s", kVectorsHelp, kInputHelp, kOutputHelp);
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
    set_vectors_input(filter, args, method);
    const auto saves = parse_save_list(args.option("save"));
    check_save_list(filter, method, saves);
    std::vector<sf_image_output> images;
    for (const auto& [name, path] : saves) images.push_back({name.c_str(), path.c_str()});
    options.images = images.data();
    options.image_count = static_cast<int64_t>(images.size());
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
