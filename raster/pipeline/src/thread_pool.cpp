#include "raster/thread_pool.hpp"

#include <chrono>

#include "raster/simd/ops.hpp"

namespace raster {

unsigned ThreadPool::hardwareThreads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : n;
}

ThreadPool::ThreadPool(unsigned threads) {
    if (threads == 0) threads = hardwareThreads();
    ranges_ = std::vector<HomeRange>(threads);
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

namespace {
// One item from a home range word (front in the low 32 bits, back in the high 32): the front one,
// or the back one, with one compare-and-swap; false when the range is empty.
bool takeItem(std::atomic<uint64_t>& front_back, bool from_back, uint32_t& item) {
    uint64_t v = front_back.load(std::memory_order_relaxed);
    for (;;) {
        const uint32_t front = uint32_t(v), back = uint32_t(v >> 32);
        if (front >= back) return false;
        const uint64_t next =
            from_back ? (uint64_t(back - 1) << 32) | front : (uint64_t(back) << 32) | (front + 1);
        if (front_back.compare_exchange_weak(v, next, std::memory_order_relaxed)) {
            item = from_back ? back - 1 : front;
            return true;
        }
    }
}
}  // namespace

bool ThreadPool::takeFront(HomeRange& range, uint32_t& item) {
    return takeItem(range.frontBack, false, item);
}

bool ThreadPool::takeBack(HomeRange& range, uint32_t& item) {
    return takeItem(range.frontBack, true, item);
}

void ThreadPool::runItems(unsigned thread) {
    const unsigned n = size();
    unsigned other = 1;  // the next range, counted from this thread's, to take from the back of
    for (;;) {
        uint32_t item;
        bool got = takeFront(ranges_[thread], item);
        // Ranges only shrink while a call runs, so one found empty stays empty. (Relaxed order is
        // enough: the job is published, and its results collected, under mutex_.)
        while (!got && other < n) {
            got = takeBack(ranges_[(thread + other) % n], item);
            if (!got) ++other;
        }
        if (!got) return;
        try {
            (*job_)(item, thread);
        } catch (...) {
            std::lock_guard lock(mutex_);
            if (!error_) error_ = std::current_exception();
            for (HomeRange& r : ranges_) r.frontBack.store(0, std::memory_order_relaxed);  // hand out no more
        }
    }
}

namespace {
// How long a thread that runs out of work polls for the next before it sleeps. Waking a sleeping
// thread through the condition variable costs about 29 µs a parallelFor on the project's machine
// (docs/PERFORMANCE.md, "Threads"), and a frame makes several calls a few µs apart; 50 µs of
// polling after each call is a small price where nothing follows.
constexpr auto kSpin = std::chrono::microseconds(50);

// Polls done() until it is true or kSpin has passed; returns done().
template <class Done>
bool spinBriefly(Done done) {
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (int i = 0; !done(); ++i) {
        simd::pause();
        if ((i & 63) == 63 && std::chrono::steady_clock::now() > until) return done();
    }
    return true;
}
}  // namespace

void ThreadPool::workerLoop(unsigned index) {
    uint64_t seen = 0;
    for (;;) {
        spinBriefly([&] { return generation_.load() != seen; });
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
        const unsigned n = size();
        for (unsigned t = 0; t < n; ++t) {
            const uint64_t front = uint64_t(count) * t / n, back = uint64_t(count) * (t + 1) / n;
            ranges_[t].frontBack.store((back << 32) | front, std::memory_order_relaxed);
        }
        busy_ = unsigned(workers_.size());
        error_ = nullptr;
        ++generation_;
    }
    wake_.notify_all();
    runItems(0);
    std::exception_ptr error;
    {
        spinBriefly([&] { return busy_.load() == 0; });
        std::unique_lock lock(mutex_);
        done_.wait(lock, [&] { return busy_ == 0; });
        job_ = nullptr;
        error = error_;
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace raster
