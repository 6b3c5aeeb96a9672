// The thread pool under the pipeline's parallel stages: every item runs once, each thread starts on
// its own home range, a blocked thread's items are taken by the others, and errors come back.
#include "raster/thread_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

namespace raster {
namespace {

// Waits until `counter` reaches `target` or ten seconds pass; true if it was reached.
bool waitFor(const std::atomic<uint32_t>& counter, uint32_t target) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (counter.load() < target) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::yield();
    }
    return true;
}

TEST(ThreadPool, EveryItemRunsOnceOnAThreadOfThePool) {
    for (unsigned threads : {1u, 2u, 3u, 8u}) {
        ThreadPool pool(threads);
        ASSERT_EQ(pool.size(), threads);
        for (uint32_t count : {0u, 1u, 2u, 7u, 100u, 1000u}) {
            std::unique_ptr<std::atomic<uint32_t>[]> runs(new std::atomic<uint32_t>[count + 1]());
            std::atomic<uint32_t> bad_thread{0};
            pool.parallelFor(count, [&](uint32_t item, unsigned thread) {
                runs[item].fetch_add(1);
                if (thread >= threads) bad_thread.fetch_add(1);
            });
            for (uint32_t i = 0; i < count; ++i)
                EXPECT_EQ(runs[i].load(), 1u) << threads << " threads, item " << i;
            EXPECT_EQ(bad_thread.load(), 0u);
        }
    }
}

// Two threads, four items: the home ranges are {0, 1} and {2, 3}, so the first item the calling
// thread (index 0) takes is 0 and the worker's is 2 (one shared counter would give the worker 1).
// Items 0 and 2 each wait until the other has started, so neither thread can take the other's.
TEST(ThreadPool, EachThreadStartsOnItsOwnHomeRange) {
    ThreadPool pool(2);
    for (int round = 0; round < 20; ++round) {
        std::atomic<uint32_t> started{0};
        uint32_t first[2] = {99, 99};  // each thread writes its own entry
        pool.parallelFor(4, [&](uint32_t item, unsigned thread) {
            if (first[thread] == 99) first[thread] = item;
            if (item % 2 == 0) {
                started.fetch_add(1);
                waitFor(started, 2);
            }
        });
        EXPECT_EQ(first[0], 0u) << "round " << round;
        EXPECT_EQ(first[1], 2u) << "round " << round;
    }
}

// Whichever thread takes the blocking item, the others must take every remaining item of its
// home range from the back, or the blocking item waits in vain.
TEST(ThreadPool, AnotherThreadTakesTheItemsOfABlockedThread) {
    for (unsigned threads : {2u, 3u}) {
        ThreadPool pool(threads);
        constexpr uint32_t kCount = 60;
        for (uint32_t blocker : {0u, 5u, kCount - 1}) {
            std::atomic<uint32_t> done{0};
            bool reached = false;
            pool.parallelFor(kCount, [&](uint32_t item, unsigned) {
                if (item == blocker)
                    reached = waitFor(done, kCount - 1);
                else
                    done.fetch_add(1);
            });
            EXPECT_TRUE(reached) << threads << " threads, blocking item " << blocker;
            EXPECT_EQ(done.load(), kCount - 1);
        }
    }
}

// Calls a few µs apart, as a frame makes them: the workers poll for the next call before they
// sleep, and no call may be missed or run twice whether it arrives while they poll or sleep.
TEST(ThreadPool, CallsInQuickSuccessionEachRunEveryItemOnce) {
    ThreadPool pool(3);
    std::atomic<uint64_t> sum{0};
    uint64_t expected = 0;
    for (uint32_t call = 0; call < 5000; ++call) {
        const uint32_t count = 2 + call % 5;
        pool.parallelFor(count, [&](uint32_t item, unsigned) { sum.fetch_add(uint64_t(call) * 8 + item); });
        for (uint32_t item = 0; item < count; ++item) expected += uint64_t(call) * 8 + item;
        ASSERT_EQ(sum.load(), expected) << "call " << call;
        if (call % 1000 == 999) std::this_thread::sleep_for(std::chrono::milliseconds(2));  // let them sleep
    }
}

// A pool destroyed right after a call, while its workers still poll, stops without hanging.
TEST(ThreadPool, DestroyedWhileItsWorkersPollItStops) {
    for (int i = 0; i < 50; ++i) {
        ThreadPool pool(2);
        std::atomic<uint32_t> ran{0};
        pool.parallelFor(4, [&](uint32_t, unsigned) { ran.fetch_add(1); });
        EXPECT_EQ(ran.load(), 4u);
    }
}

TEST(ThreadPool, AnErrorComesBackAndThePoolStaysUsable) {
    ThreadPool pool(2);
    std::atomic<uint32_t> ran{0};
    EXPECT_THROW(pool.parallelFor(1000,
                                  [&](uint32_t item, unsigned) {
                                      ran.fetch_add(1);
                                      if (item == 3) throw std::runtime_error("item 3");
                                  }),
                 std::runtime_error);
    EXPECT_GE(ran.load(), 1u);
    std::atomic<uint32_t> second{0};
    pool.parallelFor(100, [&](uint32_t, unsigned) { second.fetch_add(1); });
    EXPECT_EQ(second.load(), 100u);
}

}  // namespace
}  // namespace raster
