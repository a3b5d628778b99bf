// statfilter: the command-line tool. Built on the public C header only.
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <set>
#include <string>

#include <statfilter/statfilter.h>

#include "cli_common.hpp"
#include "commands.hpp"

namespace {

const char* const kUsage =
    "usage: statfilter COMMAND [options]\n"
    "\n"
    "Statistical temporal filtering of rendered indirect illumination.\n"
    "\n"
    "commands:\n"
    "  info PATTERN        frames, size, channels, layers and statistics of a sequence\n"
    "  copy IN OUT         read and write a sequence unchanged (checks the whole path)\n"
    "  denoise IN OUT      filter a sequence (--method, parameters: statfilter denoise --help)\n"
    "  motion IN           motion maps: alpha (1 = still) and beta (per frame, 1 = moving)\n"
    "  detect DENOISED     pixel-frames still wrong after denoising: mask, crop windows (--noisy NOISY)\n"
    "  merge DEN RR OUT    splice re-rendered pixels (full frames or crop windows) into the denoised\n"
    "  plan IN OUT -o P    the denoise run as tasks for a render farm or Dask (docs/distributed.md)\n"
    "  task PLAN N         run task N of a plan\n"
    "  compare TEST REF    error of a sequence against a reference (relMSE, PSNR, flicker)\n"
    "  report IN OUT       a review page: before/after, motion and rank maps, error per frame\n"
    "                      (-o report.html; made by the Python package: statfilter report --help)\n"
    "  plugins             every filter, built-in or plugin: kind, version, origin, parameters\n"
    "  version             print the library version\n"
    "\n"
    "Frame patterns: one # or @ per digit as in Nuke and Houdini (beauty.####.exr is beauty.0001.exr,\n"
    "beauty.@@.exr is beauty.01.exr; a lone # is 4 digits), or beauty.%04d.exr. Not oiiotool's\n"
    "convention, where #### is 16 digits. Run 'statfilter COMMAND --help' for a command's options.\n";

int print_version(int, char**) {
    std::printf("statfilter %s\n", sf_version_string());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace statfilter_cli;
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
        std::fputs(kUsage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string command = argv[1];
    install_interrupt_handlers();
    const std::map<std::string, int (*)(int, char**)> commands = {
        {"info", cmd_info},       {"copy", cmd_copy},     {"denoise", cmd_denoise}, {"compare", cmd_compare},
        {"plugins", cmd_plugins}, {"motion", cmd_motion}, {"detect", cmd_detect},   {"merge", cmd_merge},
        {"report", cmd_report},   {"plan", cmd_plan},     {"task", cmd_task},
        {"version", print_version}};
    try {
        if (command == "--version") return print_version(argc, argv);
        const auto found = commands.find(command);
        if (found != commands.end()) return found->second(argc, argv);
        std::set<std::string> names;
        for (const auto& [name, run] : commands) names.insert(name);
        const std::string nearest = nearest_name(command, names);
        throw UsageError("unknown command '" + command + "'" + (nearest.empty() ? "" : " (did you mean " + nearest + "?)"));
    } catch (const UsageError& e) {
        std::fprintf(stderr, "statfilter %s: %s\n", command.c_str(), e.what());
        return 2;
    } catch (const Failure& e) {
        if (const int signal = interrupted_by()) {
            std::fprintf(stderr, "statfilter %s: interrupted by signal %d; the output was left as it was\n",
                         command.c_str(), signal);
            return 128 + signal;
        }
        std::fprintf(stderr, "statfilter %s: error: %s\n", command.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "statfilter %s: error: %s\n", command.c_str(), e.what());
        return 1;
    }
}
