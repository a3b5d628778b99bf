// The pool a per-frame step borrows its buffers from: a returned workspace is lent again (its buffers
// kept), two lent at once are two, and with keep off or after release nothing is held.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>
#include <vector>

#include "pipeline/workspace_pool.hpp"

namespace statfilter {
namespace {

struct Buffers {
    std::vector<double> values;
};

TEST(WorkspacePool, AReturnedWorkspaceIsLentAgainWithItsBuffers) {
    WorkspacePool<Buffers> pool;
    const Buffers* first = nullptr;
    {
        auto lease = pool.borrow();
        lease->values.assign(1000, 1.5);
        first = &*lease;
    }
    auto again = pool.borrow();
    EXPECT_EQ(&*again, first);
    ASSERT_EQ(again->values.size(), 1000u);  // the caller overwrites what it reads; the storage stays
    EXPECT_EQ(again->values[999], 1.5);
}

TEST(WorkspacePool, TwoLentAtOnceAreTwo) {
    WorkspacePool<Buffers> pool;
    auto a = pool.borrow();
    auto b = pool.borrow();
    EXPECT_NE(&*a, &*b);
}

TEST(WorkspacePool, WithoutKeepOrAfterReleaseNothingIsHeld) {
    WorkspacePool<Buffers> pool;
    pool.keep(false);
    {
        auto lease = pool.borrow();
        lease->values.assign(10, 2.0);
    }
    EXPECT_TRUE(pool.borrow()->values.empty());  // a new one: the returned one went
    pool.keep(true);
    {
        auto lease = pool.borrow();
        lease->values.assign(10, 2.0);
    }
    pool.release();
    EXPECT_TRUE(pool.borrow()->values.empty());
}

TEST(WorkspacePool, ThreadsBorrowingInTurnShareAtMostAsManyAsTheyHeldAtOnce) {
    WorkspacePool<Buffers> pool;
    std::vector<const Buffers*> seen(64);
    std::vector<std::thread> threads;
    for (int t = 0; t < 2; ++t)
        threads.emplace_back([&, t] {
            for (int i = t; i < 64; i += 2) {
                auto lease = pool.borrow();
                lease->values.assign(16, static_cast<double>(i));
                seen[static_cast<size_t>(i)] = &*lease;
            }
        });
    for (auto& thread : threads) thread.join();
    std::vector<const Buffers*> distinct(seen);
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    EXPECT_LE(distinct.size(), 2u);
}

}  // namespace
}  // namespace statfilter
