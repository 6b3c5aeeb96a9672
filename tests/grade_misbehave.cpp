// A program that misbehaves on purpose, for tests/grade_sandbox_test.cpp: each mode breaks one of the
// sandbox's limits the way a submission might, and is bounded so that it stops by itself where the
// limit does not hold.
//   grade_misbehave alloc         allocates and touches 4 MiB blocks with new (up to 1 GiB); an
//                                 uncaught std::bad_alloc ends it (std::terminate: SIGABRT)
//   grade_misbehave alloc-unchecked  the same with malloc, writing through its result unchecked:
//                                 SIGSEGV on the first null
//   grade_misbehave fork N        forks up to N (≤ 1000) children that wait to be killed, prints how
//                                 many forks succeeded and how many failed with EAGAIN, kills and
//                                 reaps them; exits 1 if any fork failed
//   grade_misbehave spin          spins on the CPU for up to 60 s
//   grade_misbehave spin-ignoring-sigxcpu   the same with SIGXCPU ignored
//   grade_misbehave write FILE    writes 1 MiB blocks to FILE, up to 64 MiB
//   grade_misbehave write-ignoring-sigxfsz FILE   the same with SIGXFSZ ignored (a write fails: EFBIG)
//   grade_misbehave stdout N      writes N bytes to standard output
//   grade_misbehave crash         writes through a null pointer (SIGSEGV)
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr size_t kBlock = size_t(4) << 20;

int allocate() {
    std::vector<char*> blocks;
    for (size_t total = 0; total < (size_t(1) << 30); total += kBlock) {
        blocks.push_back(new char[kBlock]);
        std::memset(blocks.back(), 1, kBlock);
    }
    std::puts("allocated 1 GiB: no limit stopped it");
    return 0;
}

int allocateUnchecked() {
    for (size_t total = 0; total < (size_t(1) << 30); total += kBlock) {
        char* volatile block = static_cast<char*>(std::malloc(kBlock));
        std::memset(block, 1, kBlock);  // null once the address space is used up
    }
    std::puts("allocated 1 GiB: no limit stopped it");
    return 0;
}

int forkMany(int count) {
    std::vector<pid_t> children;
    int failed_again = 0, failed_other = 0, first_error = 0;
    for (int i = 0; i < count && i < 1000; ++i) {
        const pid_t pid = fork();
        if (pid == 0) {
            prctl(PR_SET_PDEATHSIG, SIGKILL);
            pause();
            _exit(0);
        }
        if (pid > 0) {
            children.push_back(pid);
        } else {
            (errno == EAGAIN ? failed_again : failed_other) += 1;
            if (!first_error) first_error = errno;
        }
    }
    std::printf("forks ok=%zu eagain=%d other=%d\n", children.size(), failed_again, failed_other);
    if (first_error) std::fprintf(stderr, "grade_misbehave: fork: %s\n", std::strerror(first_error));
    for (const pid_t pid : children) kill(pid, SIGKILL);
    for (const pid_t pid : children) waitpid(pid, nullptr, 0);
    return failed_again + failed_other > 0 ? 1 : 0;
}

int spin() {
    const auto start = std::chrono::steady_clock::now();
    volatile unsigned long counter = 0;
    while (std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
        for (int i = 0; i < 1000000; ++i) counter = counter + 1;
    std::puts("spun 60 s: no limit stopped it");
    return 0;
}

int writeFile(const char* path) {
    std::FILE* file = std::fopen(path, "wb");
    if (!file) return std::perror(path), 2;
    const std::vector<char> block(size_t(1) << 20, 'x');
    for (int i = 0; i < 64; ++i)
        if (std::fwrite(block.data(), 1, block.size(), file) != block.size() || std::fflush(file) != 0)
            return std::perror(path), 1;
    std::fclose(file);
    std::puts("wrote 64 MiB: no limit stopped it");
    return 0;
}

int writeStdout(long long bytes) {
    const std::vector<char> block(65536, 'y');
    for (long long left = bytes; left > 0; left -= (long long)block.size())
        if (std::fwrite(block.data(), 1, size_t(std::min<long long>(left, (long long)block.size())),
                        stdout) == 0)
            return 1;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "alloc") return allocate();
    if (mode == "alloc-unchecked") return allocateUnchecked();
    if (mode == "fork" && argc > 2) return forkMany(std::atoi(argv[2]));
    if (mode == "spin") return spin();
    if (mode == "spin-ignoring-sigxcpu") return signal(SIGXCPU, SIG_IGN), spin();
    if (mode == "write" && argc > 2) return writeFile(argv[2]);
    if (mode == "write-ignoring-sigxfsz" && argc > 2) return signal(SIGXFSZ, SIG_IGN), writeFile(argv[2]);
    if (mode == "stdout" && argc > 2) return writeStdout(std::atoll(argv[2]));
    if (mode == "crash") {
        volatile int* volatile nothing = nullptr;
        *nothing = 1;
        return 0;
    }
    std::fprintf(stderr,
                 "usage: grade_misbehave alloc|alloc-unchecked|fork N|spin|spin-ignoring-sigxcpu|write FILE|"
                 "write-ignoring-sigxfsz FILE|stdout N|crash\n");
    return 2;
}
