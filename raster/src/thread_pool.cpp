#include "raster/thread_pool.hpp"

namespace raster {

unsigned ThreadPool::hardwareThreads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : n;
}

ThreadPool::ThreadPool(unsigned threads) {
    if (threads == 0) threads = hardwareThreads();
    for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this, i] { workerLoop(i); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
}

void ThreadPool::runItems(unsigned thread) {
    for (;;) {
        const uint32_t item = next_.fetch_add(1, std::memory_order_relaxed);
        if (item >= count_) return;
        try {
            (*job_)(item, thread);
        } catch (...) {
            std::lock_guard lock(mutex_);
            if (!error_) error_ = std::current_exception();
            next_.store(count_, std::memory_order_relaxed);  // stop handing out more work
        }
    }
}

void ThreadPool::workerLoop(unsigned index) {
    uint64_t seen = 0;
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
        }
        runItems(index);
        {
            std::lock_guard lock(mutex_);
            if (--busy_ == 0) done_.notify_one();
        }
    }
}

void ThreadPool::parallelFor(uint32_t count, const std::function<void(uint32_t, unsigned)>& fn) {
    if (count == 0) return;
    if (workers_.empty() || count == 1) {
        for (uint32_t i = 0; i < count; ++i) fn(i, 0);
        return;
    }
    {
        std::lock_guard lock(mutex_);
        job_ = &fn;
        count_ = count;
        next_.store(0, std::memory_order_relaxed);
        busy_ = unsigned(workers_.size());
        error_ = nullptr;
        ++generation_;
    }
    wake_.notify_all();
    runItems(0);
    std::exception_ptr error;
    {
        std::unique_lock lock(mutex_);
        done_.wait(lock, [&] { return busy_ == 0; });
        job_ = nullptr;
        error = error_;
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace raster
