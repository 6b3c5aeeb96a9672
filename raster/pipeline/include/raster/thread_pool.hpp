// A fixed pool of worker threads for the pipeline's parallel stages.
//
// parallelFor gives each thread a home range of the items: n threads split [0, count) into n
// contiguous ranges, the same split for every call with the same count. A thread takes its own
// range front to back, then takes items from the back of the others' ranges until none is left.
// Why home ranges: successive calls over the same items (the clears, then each draw's tiles, frame
// after frame) then run mostly on the same core, so a tile's pixels stay in that core's caches
// instead of moving between cores with every call (docs/PERFORMANCE.md: particles on two
// threads 14.47 -> 12.34 ms a frame). Taking from the back keeps the threads busy when the ranges
// cost different amounts.
//
// Which thread runs an item still varies from run to run, so the pipeline only ever parallelises
// work whose result does not depend on that (vertex ranges written to their own slots, primitive
// chunks written to their own chunk, screen tiles that own their pixels). That is what makes
// images bit-identical for any thread count.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace raster {

class ThreadPool {
public:
    // threads == 0 means one per hardware thread. The calling thread also works, so a pool of
    // n threads starts n - 1 workers.
    explicit ThreadPool(unsigned threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const { return unsigned(workers_.size()) + 1; }

    // Calls fn(item, thread) for every item in [0, count), thread in [0, size()). Returns when all
    // are done. The first exception thrown by fn is rethrown here after the others finish.
    void parallelFor(uint32_t count, const std::function<void(uint32_t item, unsigned thread)>& fn);

    static unsigned hardwareThreads();

private:
    // One thread's home range [front, back) in one word, so that its owner (from the front) and
    // other threads (from the back) take items with one compare-and-swap each. A cache line each.
    struct alignas(64) HomeRange {
        std::atomic<uint64_t> frontBack{0};  // front in the low 32 bits, back in the high 32
    };
    static bool takeFront(HomeRange& range, uint32_t& item);
    static bool takeBack(HomeRange& range, uint32_t& item);

    void workerLoop(unsigned index);
    void runItems(unsigned thread);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(uint32_t, unsigned)>* job_ = nullptr;
    std::vector<HomeRange> ranges_;  // one per thread, index 0 the calling thread's
    // Written under mutex_; atomic so that a thread may spin on them without it (spinBriefly).
    std::atomic<unsigned> busy_{0};
    std::atomic<uint64_t> generation_{0};
    bool stop_ = false;
    std::exception_ptr error_;
};

}  // namespace raster
