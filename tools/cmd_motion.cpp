// statfilter motion IN: where a sequence moves, as maps (EXR) and false-colour previews (PNG).
#include <cstdio>

#include "cli_common.hpp"
#include "cli_images.hpp"
#include "cli_json.hpp"
#include "commands.hpp"

namespace statfilter_cli {

int cmd_motion(int argc, char** argv) {
    const Args args(argc, argv, 2, {"json", "quiet", "help"},
                    merged({kInputOptions, {"alpha", "beta", "alpha-preview", "beta-preview"}}));
    if (args.flag("help")) {
        std::printf("usage: statfilter motion IN [--alpha A.exr] [--beta B.####.exr] [options]\n\n"
                    "Motion maps of a sequence: alpha (one image, 1 = stationary, from the leading temporal\n"
                    "components) and beta (per frame, 1 = moving now, from z-scores or from the albedo/normal\n"
                    "passes given with --albedo/--normal PATTERN). Parameters: see 'motion' in\n"
                    "'statfilter denoise --help'.\n\n"
                    "  --alpha PATH            write alpha (float EXR)\n"
                    "  --beta PATTERN          write beta, one frame per input frame\n"
                    "  --alpha-preview P.png   false-colour preview of alpha\n"
                    "  --beta-preview P.####.png  false-colour previews of beta\n"
                    "  --json, --quiet\n\n%s",
                    kInputHelp);
        return 0;
    }
    if (args.positionals().size() != 1) throw UsageError("motion takes one IN pattern (see --help)");
    FilterHandle filter("motion");
    for (const auto& [name, value] : args.extras()) filter.check(sf_filter_set_string(filter.get(), name.c_str(), value.c_str()));
    ProgressLine progress(args.flag("quiet") || args.flag("json"));
    SequenceHandle input, output;
    read_input(args, args.positionals()[0], progress, input);
    const std::pair<const char*, const char*> saves[] = {
        {"alpha", "alpha"}, {"beta", "beta"}, {"alpha-preview", "alpha"}, {"beta-preview", "beta"}};
    for (const auto& [option, result] : saves)  // where each goes, checked before the maps are made
        if (args.has(option))
            check_save_outputs(filter, {{result, args.option(option)}}, args.positionals()[0], args.option("frames"), "");
    check(sf_sequence_create(input.shape(), output.out()));
    filter.check(sf_filter_set_progress(filter.get(), &ProgressLine::callback, &progress));
    filter.check(sf_filter_execute(filter.get(), input.get(), output.get()));
    for (const auto& [option, result] : saves)
        if (args.has(option)) save_image_result(filter, result, args.option(option), progress);
    progress.finish();
    double moving = 0, beta = 0;
    const char* source = "";
    filter.check(sf_filter_result_float(filter.get(), "moving_fraction", &moving));
    filter.check(sf_filter_result_float(filter.get(), "beta_fraction", &beta));
    filter.check(sf_filter_result_string(filter.get(), "beta_source", &source));
    if (args.flag("json")) {
        std::printf("{\"moving_fraction\": %s, \"beta_fraction\": %s, \"beta_source\": %s}\n", json_number(moving).c_str(),
                    json_number(beta).c_str(), json_string(source).c_str());
    } else {
        std::printf("moving (1 - mean alpha)  %.4f\nmoving now (mean beta)   %.4f (from %s)\n", moving, beta, source);
    }
    return 0;
}

}  // namespace statfilter_cli
