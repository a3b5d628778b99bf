#include "pipeline/library_threads.hpp"

#include <cblas.h>

#include <algorithm>
#include <mutex>
#include <thread>

#include <OpenImageIO/imageio.h>

namespace statfilter {
namespace {

struct Pools {
    int exr = 0, blas = 0;
};

std::mutex pools_mutex;
int running = 0;  // runs inside a LibraryThreads, in every thread
Pools found;      // the pools as the first of them found them

Pools current() {
    Pools p;
    OIIO::getattribute("exr_threads", p.exr);
    p.blas = openblas_get_num_threads();
    return p;
}

void apply(const Pools& want) {
    const Pools now = current();
    // OpenImageIO reads exr_threads when it next opens a file (0: every core; -1: none, the calling thread).
    if (want.exr != now.exr) OIIO::attribute("exr_threads", want.exr);
    if (want.blas != now.blas) openblas_set_num_threads(want.blas);
}

}  // namespace

LibraryThreads::LibraryThreads(int threads) {
    std::lock_guard<std::mutex> lock(pools_mutex);
    if (running++ > 0) return;
    found = current();
    // Never more than the pools had (a cap such as OPENBLAS_NUM_THREADS stays). One thread: the coders'
    // work is done in the calling thread (exr_threads -1), not on one pool thread beside it.
    const int n = std::max(threads, 1);
    const int exr = found.exr == 0 ? static_cast<int>(std::thread::hardware_concurrency()) : found.exr;  // 0: every core
    apply(Pools{exr < 0 || n == 1 ? -1 : std::min(n, std::max(exr, 1)), std::min(n, std::max(found.blas, 1))});
}

LibraryThreads::~LibraryThreads() {
    std::lock_guard<std::mutex> lock(pools_mutex);
    if (--running == 0) apply(found);
}

}  // namespace statfilter
