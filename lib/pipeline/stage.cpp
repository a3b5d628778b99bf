#include "pipeline/stage.hpp"

#include "pipeline/parallel.hpp"

namespace statfilter {

void run_in_memory(StreamStage& stage, const Sequence& input, Sequence& output, const Progress& progress,
                   double budget_bytes, Results& results, const GuideSources& passes) {
    auto source = memory_source(input);
    auto sink = memory_sink(output);
    StageContext context;
    context.threads = resolve_threads(0);
    context.budget_bytes = budget_bytes;
    context.progress = &progress;
    context.passes = passes;
    stage.run(*source, [&](int64_t f, float* pixels) { sink->write_frame(f, pixels); }, context, results);
    sink->commit();
}

}  // namespace statfilter
