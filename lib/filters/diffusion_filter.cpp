// The single-frame filter: anisotropic diffusion of every frame, frames in parallel.
#include "filters/builtin_filters.hpp"
#include "filters/temporal_params.hpp"
#include "pipeline/parallel.hpp"
#include "pipeline/frame_stream_stage.hpp"
#include "statfilter/anisotropic_diffusion.hpp"
#include "statfilter/nonfinite.hpp"

namespace statfilter {

std::vector<ParamSpec> diffusion_params() {
    return {
        // Defaults measured on cornell_moving at 4 spp (docs/methods.md).
        choice_param("flux", "perona-malik", {"study", "perona-malik"},
                     "conductance: 1/sqrt(1 + |grad|^2/K^2) (the study) or exp(-(|grad|/K)^2) (Perona-Malik)"),
        float_param("k", "2", 1e-9, 1e9, "edge threshold K, in units of the frame's own gradient noise"),
        int_param("iterations", "10", 0, 100000, "explicit diffusion steps"),
        float_param("dt", "0.25", 1e-6, 0.25, "time step; 0.25 is the stability limit of the explicit scheme"),
        choice_param("domain", "log", {"log", "log-values", "linear"},
                     "log: edges measured on log-compressed values (HDR), the linear values diffused (each frame "
                     "keeps its mean, no negative output for non-negative input); log-values: the log values "
                     "diffused and undone (biased low); linear: raw values throughout"),
        float_param("epsilon", "0.01", 1e-30, 1e6,
                    "log domain: levels below epsilon x the frame's mean magnitude are treated as flat"),
    };
}

DiffusionOptions diffusion_options(const ParamSet& p) {
    DiffusionOptions o;
    o.flux = parse_diffusion_flux(p.get_string("flux"));
    o.k = p.get_float("k");
    o.iterations = static_cast<int>(p.get_int("iterations"));
    o.dt = p.get_float("dt");
    o.log_domain = p.get_string("domain") != "linear";
    o.conserve = p.get_string("domain") == "log";
    o.epsilon = p.get_float("epsilon");
    return o;
}

void diffuse_sequence(const Sequence& input, Sequence& output, const DiffusionOptions& options, const Progress& progress,
                      std::vector<DiffusionWorkspace>& workspaces) {
    const Shape& s = input.shape();
    check_nonfinite(input, NonFinitePolicy::Error);
    const int threads = resolve_threads(0);
    const int workers = worker_count(s.frames, threads);
    if (static_cast<int>(workspaces.size()) < workers) workspaces.resize(static_cast<size_t>(workers));
    // Contiguous output (a frame stage's, in place): each frame is diffused where it is written.
    const int64_t samples = s.pixels() * s.channels;
    const bool direct = output.is_contiguous();
    const bool in_place = direct && input.is_contiguous() && input.data() == output.data();
    std::vector<std::vector<float>> frames(direct ? 0 : static_cast<size_t>(workers));
    parallel_for_workers(s.frames, threads, [&](int64_t f, int worker) {
        float* frame = nullptr;
        if (direct) {
            frame = output.data() + f * samples;
        } else {
            frames[static_cast<size_t>(worker)].resize(static_cast<size_t>(samples));
            frame = frames[static_cast<size_t>(worker)].data();
        }
        if (!in_place) input.get_frame(f, frame);
        diffuse_frame(frame, s.width, s.height, s.channels, options, workspaces[static_cast<size_t>(worker)]);
        if (!direct) output.set_frame(f, frame);
    }, {progress, 0, 1, "diffusion"});
}

namespace {

class DiffusionFilter final : public Filter {
public:
    DiffusionFilter() : Filter(diffusion_params()) {}

    std::unique_ptr<StreamStage> stream_stage() const override {
        const ParamSet configured = params();
        return std::make_unique<FrameStreamStage>([configured] {
            auto filter = make_diffusion_filter();
            filter->params() = configured;
            return filter;
        });
    }
    Footprint footprint() const override {
        Footprint f = stream_stage()->footprint();
        f.halo = params().get_int("iterations");  // each explicit step reaches one pixel further
        return f;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        diffuse_sequence(input, output, diffusion_options(params()), progress, workspaces_);
        // Run frame by frame (a prefilter or postfilter borrowed from a pool, one instance per thread,
        // whose working set the run counts for its whole length), the buffers serve the next frame;
        // after a whole shot they go.
        if (input.shape().frames > 1) workspaces_.clear();
    }

private:
    std::vector<DiffusionWorkspace> workspaces_;
};

}  // namespace

std::unique_ptr<Filter> make_diffusion_filter() { return std::make_unique<DiffusionFilter>(); }

}  // namespace statfilter
