// The motion maps on their own: the output is the input unchanged; alpha and beta are image results.
#include "filters/builtin_filters.hpp"
#include "filters/motion_analysis.hpp"
#include "filters/temporal_params.hpp"

namespace statfilter {
namespace {

double mean_of(const Sequence& s) {
    double sum = 0;
    const Shape& sh = s.shape();
    for (int64_t f = 0; f < sh.frames; ++f)
        for (int64_t y = 0; y < sh.height; ++y)
            for (int64_t x = 0; x < sh.width; ++x) sum += s.at(f, y, x, 0);
    return sum / static_cast<double>(sh.frames * sh.pixels());
}

class MotionFilter final : public Filter {
public:
    MotionFilter() : Filter(make_params()) {
        for (const char* pass : {"albedo", "normal"}) accept_input(pass);
        declare_image_result("alpha");
        declare_image_result("beta", ImageFrames::PerFrame);
    }

    static std::vector<ParamSpec> make_params() {
        std::vector<ParamSpec> p = motion_params();
        for (auto& c : temporal_common_params()) p.push_back(c);
        return p;
    }

protected:
    void run(const Sequence& input, Sequence& output, const Progress& progress) override {
        const MotionMaps maps = compute_motion(input, guide_passes(*this, input, params()), params(), {progress, 0.0, 1.0, "motion"});
        output.copy_samples_from(input);
        mutable_results().set("moving_fraction", 1.0 - mean_of(*maps.alpha));
        mutable_results().set("beta_fraction", mean_of(*maps.beta));
        mutable_results().set("beta_source", maps.beta_source);
        mutable_results().set_image("alpha", maps.alpha);
        mutable_results().set_image("beta", maps.beta);
    }
};

}  // namespace

double mean_of_map(const Sequence& map) { return mean_of(map); }

std::unique_ptr<Filter> make_motion_filter() { return std::make_unique<MotionFilter>(); }

}  // namespace statfilter
