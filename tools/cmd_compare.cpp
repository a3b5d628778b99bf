// statfilter compare TEST REF: the error of a sequence against a reference.
#include <cstdio>

#include "cli_common.hpp"
#include "cli_json.hpp"
#include "commands.hpp"

namespace statfilter_cli {

int cmd_compare(int argc, char** argv) {
    const Args args(argc, argv, 2, {"json", "quiet", "help"}, kInputOptions, {});
    if (args.flag("help")) {
        std::printf("usage: statfilter compare TEST REF [options]\n\n"
                    "Error of TEST against the reference REF (same frames, size and channels):\n"
                    "relMSE overall, inside the moving region and outside it, PSNR of tonemapped values,\n"
                    "temporal flicker and still-scene jitter.\n\n%s  --json, --quiet\n",
                    kInputHelp);
        return 0;
    }
    if (args.positionals().size() != 2) throw UsageError("expected TEST and REF patterns (see --help)");
    ProgressLine progress(args.flag("quiet") || args.flag("json"));
    SequenceHandle test, ref;
    read_input(args, args.positionals()[0], progress, test);
    read_input(args, args.positionals()[1], progress, ref);
    progress.finish();
    sf_comparison c;
    sf_comparison_init(&c);
    check(sf_sequence_compare(test.get(), ref.get(), &c));
    const std::pair<const char*, double> rows[] = {
        {"rel_mse", c.rel_mse}, {"rel_mse_moving", c.rel_mse_moving}, {"rel_mse_static", c.rel_mse_static},
        {"moving_fraction", c.moving_fraction}, {"psnr", c.psnr}, {"flicker", c.flicker}, {"jitter", c.jitter}};
    if (args.flag("json")) {
        std::string j = "{";
        for (const auto& [name, value] : rows) j += std::string(j.size() > 1 ? ", " : "") + json_string(name) + ": " + json_number(value);
        std::printf("%s}\n", j.c_str());
    } else {
        for (const auto& [name, value] : rows) std::printf("%-16s %.6g\n", name, value);
    }
    return 0;
}

}  // namespace statfilter_cli
