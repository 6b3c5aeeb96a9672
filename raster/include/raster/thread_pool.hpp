// A fixed pool of worker threads for the pipeline's parallel stages.
//
// parallelFor hands out work items through one atomic counter; which thread runs an item varies
// from run to run, so the pipeline only ever parallelises work whose result does not depend on
// that (vertex ranges written to their own slots, primitive chunks written to their own chunk,
// screen tiles that own their pixels). That is what makes images bit-identical for any thread count.
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
    void workerLoop(unsigned index);
    void runItems(unsigned thread);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(uint32_t, unsigned)>* job_ = nullptr;
    uint32_t count_ = 0;
    std::atomic<uint32_t> next_{0};
    unsigned busy_ = 0;
    uint64_t generation_ = 0;
    bool stop_ = false;
    std::exception_ptr error_;
};

}  // namespace raster
