// A run's thread count reaches the thread pools of the libraries it calls (OpenEXR's coders through
// OpenImageIO, OpenBLAS) while it runs, and they are put back as they were after it.
#include <gtest/gtest.h>

#include <cblas.h>

#include <OpenImageIO/imageio.h>

#include "pipeline/library_threads.hpp"
#include "pipeline/parallel.hpp"
#include "statfilter/filter.hpp"
#include "statfilter/filter_registry.hpp"

namespace {

using namespace statfilter;

struct Pools {
    int exr = 0, blas = 0;
};

Pools pools() {
    Pools p;
    OIIO::getattribute("exr_threads", p.exr);
    p.blas = openblas_get_num_threads();
    return p;
}

void expect_same(const Pools& a, const Pools& b) {
    EXPECT_EQ(a.exr, b.exr);
    EXPECT_EQ(a.blas, b.blas);
}

void expect_one_thread(const Pools& p) {
    EXPECT_EQ(p.exr, -1);  // OpenEXR codes in the calling thread
    EXPECT_EQ(p.blas, 1);
}

TEST(LibraryThreads, OneThreadThenPutBackAsFound) {
    const Pools before = pools();
    {
        const LibraryThreads one(1);
        expect_one_thread(pools());
        {
            const LibraryThreads overlapping(3);  // a run starting meanwhile leaves the pools in use alone
            expect_one_thread(pools());
        }
        expect_one_thread(pools());  // and does not put them back under the first
    }
    expect_same(pools(), before);
}

TEST(LibraryThreads, NeverMoreThanThePoolsHad) {
    const Pools before = pools();
    OIIO::attribute("exr_threads", 2);
    openblas_set_num_threads(1);  // as OPENBLAS_NUM_THREADS=1 leaves it
    {
        const LibraryThreads three(3);
        const Pools p = pools();
        EXPECT_EQ(p.exr, 2);
        EXPECT_EQ(p.blas, 1);
    }
    EXPECT_EQ(pools().exr, 2);
    EXPECT_EQ(pools().blas, 1);
    OIIO::attribute("exr_threads", 3);
    {
        const LibraryThreads two(2);
        EXPECT_EQ(pools().exr, 2);
    }
    EXPECT_EQ(pools().exr, 3);
    OIIO::attribute("exr_threads", before.exr);
    openblas_set_num_threads(before.blas);
}

TEST(LibraryThreads, ARunOnOneThreadUsesOneThreadInItsLibraries) {
    const Pools before = pools();
    auto filter = create_filter("pca");
    Sequence in(Shape{8, 12, 10, 3}), out(Shape{8, 12, 10, 3});
    for (int64_t f = 0; f < 8; ++f)
        for (int64_t y = 0; y < 12; ++y)
            for (int64_t x = 0; x < 10; ++x)
                for (int64_t c = 0; c < 3; ++c) in.at(f, y, x, c) = 1.0f + 0.01f * static_cast<float>((f * 7 + y * 3 + x + c) % 11);
    int calls = 0;
    Pools during;
    const Progress progress([&](double, const char*) {  // called on the running thread, during the run
        if (calls++ == 1) during = pools();
        return true;
    });
    {
        const ThreadLimit limit(1);  // what --threads 1 sets for the run
        filter->execute(in, out, progress);
    }
    ASSERT_GT(calls, 1);
    expect_one_thread(during);
    expect_same(pools(), before);
}

}  // namespace
