// statfilter: the command-line tool. Built on the public C header only.
#include <cstdio>
#include <cstring>
#include <exception>

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
    "  compare TEST REF    error of a sequence against a reference (relMSE, PSNR, flicker)\n"
    "  plugins             every filter, built-in or plugin: kind, version, origin, parameters\n"
    "  version             print the library version\n"
    "\n"
    "Frame patterns: one # or @ per digit as in Nuke and Houdini (beauty.####.exr is beauty.0001.exr,\n"
    "beauty.@@.exr is beauty.01.exr; a lone # is 4 digits), or beauty.%04d.exr. Not oiiotool's\n"
    "convention, where #### is 16 digits. Run 'statfilter COMMAND --help' for a command's options.\n";

}  // namespace

int main(int argc, char** argv) {
    using namespace statfilter_cli;
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
        std::fputs(kUsage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string command = argv[1];
    try {
        if (command == "info") return cmd_info(argc, argv);
        if (command == "copy") return cmd_copy(argc, argv);
        if (command == "denoise") return cmd_denoise(argc, argv);
        if (command == "compare") return cmd_compare(argc, argv);
        if (command == "plugins") return cmd_plugins(argc, argv);
        if (command == "motion") return cmd_motion(argc, argv);
        if (command == "detect") return cmd_detect(argc, argv);
        if (command == "merge") return cmd_merge(argc, argv);
        if (command == "version" || command == "--version") {
            std::printf("statfilter %s\n", sf_version_string());
            return 0;
        }
        throw UsageError("unknown command '" + command + "'");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "statfilter %s: %s\n", command.c_str(), e.what());
        return 2;
    } catch (const Failure& e) {
        std::fprintf(stderr, "statfilter %s: error: %s\n", command.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "statfilter %s: error: %s\n", command.c_str(), e.what());
        return 1;
    }
}
