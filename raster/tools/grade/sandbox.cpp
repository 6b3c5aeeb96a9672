// runSandboxed: the child's set-up between fork and exec, the parent's watch over it, and the words
// for how it ended (sandbox.hpp says what and why).
#include "grade/sandbox.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <pwd.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <tuple>
#include <utility>

#include "raster/check.hpp"

extern char** environ;

namespace raster::grade {
namespace {

using Clock = std::chrono::steady_clock;

// How long the sandbox still reads the child's pipes after the child has ended and its group has been
// killed: enough for the kernel to close the pipes of the killed, too short for a process that left
// the group and keeps a pipe open to hold runSandboxed up.
constexpr auto kDrainGrace = std::chrono::milliseconds(250);
// How often the parent looks at the child where the kernel has no pidfd to wake it when it ends.
constexpr int kTickMs = 10;
// A peak resident size of this share of the address-space limit counts as evidence of an allocation
// failure in a crash (sandbox.hpp).
constexpr double kMemoryEvidenceShare = 0.75;

std::string errnoText(int error) {
    return std::strerror(error);
}

// A file descriptor that closes itself.
class Fd {
  public:
    Fd() = default;
    explicit Fd(int fd) : fd_(fd) {}
    Fd(Fd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
    Fd& operator=(Fd&& other) noexcept {
        std::swap(fd_, other.fd_);
        return *this;
    }
    ~Fd() { reset(); }
    int get() const { return fd_; }
    int release() { return std::exchange(fd_, -1); }
    void reset() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }

  private:
    int fd_ = -1;
};

struct Pipe {
    Fd read, write;
};

Pipe makePipe(const char* what) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
        throw Error(ErrorCode::InvalidState,
                    std::string("cannot make the pipe for the child's ") + what + ": " + errnoText(errno));
    fcntl(fds[0], F_SETFL, O_NONBLOCK);
    return {Fd(fds[0]), Fd(fds[1])};
}

// ---- The child, between fork and exec ----

// The step before exec that failed, reported to the parent through the start pipe with its errno.
enum class StartStep : int32_t {
    Descriptors,
    Isolation,
    Limits,
    Groups,
    GroupId,
    UserId,
    Directory,
    ParentDeath,
    Exec
};
struct StartFailure {
    StartStep step;
    int32_t error;
};

const char* startStepText(StartStep step) {
    switch (step) {
        case StartStep::Descriptors:
            return "setting up its standard streams";
        case StartStep::Isolation:
            return "landlock_restrict_self";
        case StartStep::Limits:
            return "setrlimit";
        case StartStep::Groups:
            return "setgroups";
        case StartStep::GroupId:
            return "setgid";
        case StartStep::UserId:
            return "setuid";
        case StartStep::Directory:
            return "chdir to the working directory";
        case StartStep::ParentDeath:
            return "prctl(PR_SET_PDEATHSIG)";
        case StartStep::Exec:
            return "execvp";
    }
    return "set-up";
}

// All the child needs, made before fork: the caller may have other threads, so between fork and exec
// the child only makes async-signal-safe calls and allocates nothing.
struct ChildPlan {
    std::vector<char*> argv, envp;  // each null-terminated
    const char* directory = nullptr;
    std::vector<std::pair<int, rlimit>> limits;
    bool drop = false;
    uid_t uid = 0;
    gid_t gid = 0;
    int stdinFd = -1, stdoutFd = -1, stderrFd = -1, reportFd = -1;
    int landlockRuleset = -1;  // applied once the standard streams are in place; -1: none
    pid_t parent = 0;
};

[[noreturn]] void failStart(int report_fd, StartStep step) {
    const StartFailure failure{step, errno};
    [[maybe_unused]] const ssize_t written = ::write(report_fd, &failure, sizeof failure);
    _exit(127);
}

// Closes every descriptor above 2 but `keep`.
void closeOthers(int keep) {
    const bool ranges = syscall(SYS_close_range, 3u, unsigned(keep - 1), 0u) == 0 &&
                        syscall(SYS_close_range, unsigned(keep + 1), ~0u, 0u) == 0;
    if (ranges) return;
    rlimit files{};
    const int most = getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur != RLIM_INFINITY
                         ? int(std::min<rlim_t>(files.rlim_cur, 1 << 20))
                         : 65536;
    for (int fd = 3; fd < most; ++fd)
        if (fd != keep) ::close(fd);
}

void resetSignals() {
    struct sigaction action {};
    action.sa_handler = SIG_DFL;
    sigemptyset(&action.sa_mask);
    for (int s = 1; s < NSIG; ++s)
        if (s != SIGKILL && s != SIGSTOP) sigaction(s, &action, nullptr);  // glibc's reserved ones refuse
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
}

[[noreturn]] void runChild(const ChildPlan& plan) {
    setpgid(0, 0);
    // Every source above 9 first, so that no dup2 below overwrites a descriptor still to be copied.
    const int report = fcntl(plan.reportFd, F_DUPFD_CLOEXEC, 10);
    if (report < 0) failStart(plan.reportFd, StartStep::Descriptors);
    const int sources[3] = {plan.stdinFd, plan.stdoutFd, plan.stderrFd};
    int moved[3];
    for (int i = 0; i < 3; ++i)
        if ((moved[i] = fcntl(sources[i], F_DUPFD_CLOEXEC, 10)) < 0)
            failStart(report, StartStep::Descriptors);
    for (int i = 0; i < 3; ++i)
        if (dup2(moved[i], i) < 0) failStart(report, StartStep::Descriptors);
    // Before the descriptors close (the ruleset is one of them); the drop and chdir below are not
    // file accesses that Landlock governs, and execvp is one that it does.
    if (plan.landlockRuleset >= 0 && applyLandlock(plan.landlockRuleset) != 0)
        failStart(report, StartStep::Isolation);
    closeOthers(report);
    for (const auto& [resource, value] : plan.limits)
        if (setrlimit(resource, &value) != 0) failStart(report, StartStep::Limits);
    if (plan.drop) {
        if (setgroups(1, &plan.gid) != 0) failStart(report, StartStep::Groups);
        if (setgid(plan.gid) != 0) failStart(report, StartStep::GroupId);
        if (setuid(plan.uid) != 0) failStart(report, StartStep::UserId);
    }
    // After the drop, so that the directory is entered with the child's own permissions.
    if (plan.directory && chdir(plan.directory) != 0) failStart(report, StartStep::Directory);
    // After the drop too: a change of credentials clears the parent-death signal.
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) failStart(report, StartStep::ParentDeath);
    if (getppid() != plan.parent) _exit(127);  // the parent died before the line above
    resetSignals();
    environ = const_cast<char**>(plan.envp.data());  // execvp looks argv[0] up on this environment's PATH
    execvp(plan.argv[0], plan.argv.data());
    failStart(report, StartStep::Exec);
}

// ---- The parent: preparation ----

struct RunAs {
    bool drop = false;
    uid_t uid = 0;
    gid_t gid = 0;
};

RunAs resolveUser(const SandboxCommand& command, std::vector<std::string>& warnings) {
    RunAs run{false, geteuid(), getegid()};
    if (!command.dropToUser) return run;
    passwd entry{};
    passwd* user = nullptr;
    std::vector<char> buffer(16384);
    getpwnam_r(command.dropToUser->c_str(), &entry, buffer.data(), buffer.size(), &user);  // thread-safe
    RASTER_REQUIRE(user, InvalidArgument,
                   "no user '" + *command.dropToUser + "' to run the sandboxed command as (getpwnam)");
    if (geteuid() == 0)
        run = {true, user->pw_uid, user->pw_gid};
    else if (user->pw_uid != geteuid())
        warnings.push_back("not root: cannot run as '" + *command.dropToUser + "', the child runs as uid " +
                           std::to_string(geteuid()));
    return run;
}

// Gives `directory` and everything below it to the child's user (links themselves, not their targets).
void handOver(const std::string& directory, const RunAs& run) {
    namespace fs = std::filesystem;
    auto own = [&](const fs::path& path) {
        if (lchown(path.c_str(), run.uid, run.gid) != 0)
            throw Error(ErrorCode::BadFile, "cannot give " + path.string() + " to uid " +
                                                std::to_string(run.uid) +
                                                " for the sandbox: " + errnoText(errno));
    };
    own(directory);
    std::error_code error;
    for (fs::recursive_directory_iterator it(directory, error), end; !error && it != end; it.increment(error))
        own(it->path());
    if (error)
        throw Error(ErrorCode::BadFile,
                    "cannot list the scratch directory " + directory + ": " + error.message());
}

void requireDirectory(const std::string& path, const char* what) {
    std::error_code error;
    RASTER_REQUIRE(path.empty() || std::filesystem::is_directory(path, error), BadFile,
                   std::string("the sandbox's ") + what + " " + path + " is not a directory");
}

// The rlimits, each no higher than the caller's own hard limit where the caller may not raise it.
std::vector<std::pair<int, rlimit>> planLimits(const SandboxLimits& limits) {
    std::vector<std::pair<int, rlimit>> planned;
    auto add = [&](int resource, uint64_t soft, uint64_t hard) {
        rlimit current{};
        if (geteuid() != 0 && getrlimit(resource, &current) == 0 && current.rlim_max != RLIM_INFINITY) {
            soft = std::min<uint64_t>(soft, current.rlim_max);
            hard = std::min<uint64_t>(hard, current.rlim_max);
        }
        planned.push_back({resource, rlimit{rlim_t(soft), rlim_t(hard)}});
    };
    if (limits.cpuSeconds > 0) add(RLIMIT_CPU, limits.cpuSeconds, limits.cpuSeconds + 1);
    if (limits.addressSpaceBytes > 0) add(RLIMIT_AS, limits.addressSpaceBytes, limits.addressSpaceBytes);
    if (limits.processes > 0) add(RLIMIT_NPROC, limits.processes, limits.processes);
    if (limits.fileSizeBytes > 0) add(RLIMIT_FSIZE, limits.fileSizeBytes, limits.fileSizeBytes);
    add(RLIMIT_CORE, 0, 0);
    return planned;
}

// ---- The parent: file-system isolation ----

// The first line of `text`, for a reason.
std::string firstLine(const std::string& text) {
    return text.substr(0, std::min(text.find('\n'), size_t(200)));
}

IsolationChoice probeIsolation(const std::optional<std::string>& drop_to_user) {
    std::string landlock_why;
    const int abi = landlockAbi(&landlock_why);
    if (abi > 0) return {Isolation::Landlock, "Landlock ABI " + std::to_string(abi)};
    std::string bwrap_why;
    const std::string bwrap = findBubblewrap();
    if (bwrap.empty()) {
        bwrap_why = "no bwrap in /usr/local/bin, /usr/bin or /bin: Debian's bubblewrap package";
    } else {
        SandboxCommand probe;
        probe.argv = bubblewrapArgv(bwrap, {{"/usr", "/bin", "/lib", "/lib64"}, {}}, "/", {"true"});
        probe.dropToUser = drop_to_user;
        probe.limits = {10, 10, 0, 0, 0, 4096, 4096};
        const SandboxResult r = runSandboxed(probe);
        if (r.succeeded()) return {Isolation::Bubblewrap, "bubblewrap (" + bwrap + ")"};
        bwrap_why =
            bwrap + " does not run here: " + (r.stderrText.empty() ? r.description : firstLine(r.stderrText));
    }
    return {Isolation::None, "no file-system isolation: Landlock unavailable (" + landlock_why +
                                 "); bubblewrap unavailable (" + bwrap_why + ")"};
}

// How a command's `files` will hold: the isolation, and Landlock's ruleset or bwrap's command line.
struct Confinement {
    Isolation isolation = Isolation::None;
    Fd ruleset;
    std::vector<std::string> argv;  // what the child executes
};

Confinement confine(const SandboxCommand& command, std::vector<std::string>& warnings) {
    Confinement c;
    c.argv = command.argv;
    if (!command.files) return c;
    Isolation isolation = command.isolation;
    std::string why = "no file-system isolation: the command asked for none";
    if (isolation == Isolation::Auto) {
        const IsolationChoice choice = isolationFor(command.dropToUser);
        isolation = choice.isolation;
        why = choice.description;
    }
    if (isolation == Isolation::Landlock) {
        const int abi = landlockAbi(&why);
        RASTER_REQUIRE(abi > 0, InvalidState, "Landlock isolation asked for: " + why);
        c.ruleset = Fd(makeLandlockRuleset(*command.files, abi));
    } else if (isolation == Isolation::Bubblewrap) {
        const std::string bwrap = findBubblewrap();
        RASTER_REQUIRE(!bwrap.empty(), InvalidState,
                       "bubblewrap isolation asked for: no bwrap in /usr/local/bin, /usr/bin or /bin");
        c.argv = bubblewrapArgv(bwrap, *command.files, command.workingDirectory, command.argv);
    } else {
        warnings.push_back(why);
    }
    c.isolation = isolation;
    return c;
}

// ---- The parent: watching ----

// One of the child's pipes as the parent reads it.
struct Stream {
    int fd = -1;
    size_t keep = 0;  // bytes kept at most
    std::string kept;
    uint64_t total = 0;
};

// Reads what the pipe holds now (at most 64 MiB, so that a writer as fast as this loop cannot keep the
// parent from its clock), keeping the first `keep` bytes; closes it at its end.
void drain(Stream& stream) {
    char buffer[65536];
    for (int reads = 0; reads < 1024; ++reads) {
        const ssize_t n = ::read(stream.fd, buffer, sizeof buffer);
        if (n > 0) {
            stream.total += uint64_t(n);
            if (stream.kept.size() < stream.keep)
                stream.kept.append(buffer, std::min(size_t(n), stream.keep - stream.kept.size()));
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && errno == EAGAIN) return;
        ::close(stream.fd);  // end of file, or an error after which nothing more can be read
        stream.fd = -1;
        return;
    }
}

struct Ending {
    int status = 0;
    rusage usage{};
    bool lost = false;  // reaped by someone else in this process (a waitpid(-1)): status unknown
    bool wallKilled = false;
    double wallSeconds = 0;
};

bool hasEnded(pid_t pid) {
    siginfo_t info{};
    if (waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) != 0) return errno == ECHILD;  // gone
    return info.si_pid == pid;
}

int openPidFd(pid_t pid) {
#ifdef SYS_pidfd_open
    return int(syscall(SYS_pidfd_open, pid, 0));
#else
    (void)pid;
    return -1;
#endif
}

int millisecondsUntil(Clock::time_point when, Clock::time_point now) {
    const auto ms = std::chrono::ceil<std::chrono::milliseconds>(when - now).count();
    return int(std::clamp<long long>(ms, 1, 1000));
}

// Reads the pipes until the child has ended and they are closed (or kDrainGrace after its end), killing
// the child's process group at the wall-clock limit and when the child ends; reaps the child.
Ending watch(pid_t pid, std::array<Stream*, 3> streams, double wall_limit, Clock::time_point start) {
    Fd pidfd(openPidFd(pid));
    const auto deadline =
        wall_limit > 0
            ? start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wall_limit))
            : Clock::time_point::max();
    Ending ending;
    bool ended = false;
    Clock::time_point ended_at;
    for (;;) {
        if (!ended && hasEnded(pid)) {
            kill(-pid, SIGKILL);  // what it left behind; its zombie keeps the group id from reuse till now
            int reaped;
            while ((reaped = wait4(pid, &ending.status, 0, &ending.usage)) < 0 && errno == EINTR) {
            }
            ending.lost = reaped != pid;
            ended = true;
            ended_at = Clock::now();
            ending.wallSeconds = std::chrono::duration<double>(ended_at - start).count();
            pidfd.reset();
        }
        const auto now = Clock::now();
        const bool open =
            std::any_of(streams.begin(), streams.end(), [](const Stream* s) { return s->fd >= 0; });
        if (ended && (!open || now - ended_at >= kDrainGrace)) break;
        if (!ended && !ending.wallKilled && now >= deadline) {
            kill(-pid, SIGKILL);
            kill(pid, SIGKILL);  // in case it had not joined its group yet
            ending.wallKilled = true;
        }
        int timeout = kTickMs;
        if (ended)
            timeout = millisecondsUntil(ended_at + kDrainGrace, now);
        else if (!ending.wallKilled && pidfd.get() >= 0)
            timeout = deadline == Clock::time_point::max() ? 1000 : millisecondsUntil(deadline, now);
        else if (!ending.wallKilled)
            timeout = std::min(kTickMs, millisecondsUntil(deadline, now));
        std::array<pollfd, 4> fds{};
        nfds_t count = 0;
        for (const Stream* s : streams)
            if (s->fd >= 0) fds[count++] = {s->fd, POLLIN, 0};
        if (pidfd.get() >= 0) fds[count++] = {pidfd.get(), POLLIN, 0};
        poll(fds.data(), count, timeout);  // EINTR: look again
        for (Stream* s : streams)
            if (s->fd >= 0) drain(*s);
    }
    for (Stream* s : streams)
        if (s->fd >= 0) ::close(s->fd), s->fd = -1;
    return ending;
}

// ---- How it ended, in words ----

std::string secondsText(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f s", seconds);
    return text;
}

std::string limitSecondsText(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%g s", seconds);
    return text;
}

// The phrases of sandbox.hpp that tell a limit from what the child printed, in lower case.
constexpr const char* kMemorySigns[] = {"bad_alloc", "out of memory", "outofmemory", "cannot allocate memory",
                                        "memory exhausted"};
constexpr const char* kProcessSigns[] = {"resource temporarily unavailable", "cannot fork", "fork: retry"};
constexpr const char* kFileSizeSigns[] = {"file too large"};

// "stderr says "<the line holding the first sign>"" (at most 120 bytes of it), or nothing.
template <size_t N>
std::string findSign(const std::string& text, const char* const (&signs)[N]) {
    std::string lower(text);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    size_t at = std::string::npos;
    for (const char* sign : signs) at = std::min(at, lower.find(sign));
    if (at == std::string::npos) return {};
    const size_t begin = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
    const size_t end = std::min(text.find('\n', at), text.size());
    std::string line = text.substr(begin, std::min<size_t>(end - begin, 120));
    while (!line.empty() && std::isspace((unsigned char)line.back())) line.pop_back();
    return "stderr says \"" + line + "\"";
}

std::string endingText(const SandboxResult& result) {
    if (result.exitStatus) return "exited with status " + std::to_string(*result.exitStatus);
    return "killed by signal " + std::to_string(result.signal) + ": " + signalDescription(result.signal);
}

// A limit told from what a failed child printed or from its size at a crash, as sandbox.hpp says.
bool describeFailure(SandboxResult& result, const SandboxLimits& limits) {
    const std::string how = endingText(result);
    std::string evidence = findSign(result.stderrText, kMemorySigns);
    const int s = result.signal;
    if (evidence.empty() && limits.addressSpaceBytes > 0 && (s == SIGSEGV || s == SIGBUS || s == SIGABRT) &&
        double(result.peakRssBytes) >= kMemoryEvidenceShare * double(limits.addressSpaceBytes))
        evidence =
            "peak resident size " + formatBytes(result.peakRssBytes) + ", " +
            std::to_string(int(100.0 * double(result.peakRssBytes) / double(limits.addressSpaceBytes))) +
            " % of the limit, before the crash";
    if (!evidence.empty()) {
        result.outcome = SandboxOutcome::MemoryLimit;
        result.description = (limits.addressSpaceBytes > 0
                                  ? "memory limit of " + formatBytes(limits.addressSpaceBytes) + " exceeded: "
                                  : std::string("out of memory: ")) +
                             evidence + "; " + how;
    } else if (limits.processes > 0 && !(evidence = findSign(result.stderrText, kProcessSigns)).empty()) {
        result.outcome = SandboxOutcome::ProcessLimit;
        result.description =
            "process limit of " + std::to_string(limits.processes) + " reached: " + evidence + "; " + how;
    } else if (limits.fileSizeBytes > 0 &&
               !(evidence = findSign(result.stderrText, kFileSizeSigns)).empty()) {
        result.outcome = SandboxOutcome::OutputSizeLimit;
        result.description = "output-size limit of " + formatBytes(limits.fileSizeBytes) +
                             " exceeded: " + evidence + "; " + how;
    }
    result.evidence = evidence;
    return !evidence.empty();
}

// Sets outcome, description and evidence from how the child ended (after the pipes were read).
void describe(SandboxResult& result, const Ending& ending, const SandboxLimits& limits) {
    if (ending.lost) {
        result.outcome = SandboxOutcome::Exited;  // with no exitStatus: not a success
        result.description = "ended, but how is unknown: another waitpid in this process reaped it";
        return;
    }
    if (WIFEXITED(ending.status))
        result.exitStatus = WEXITSTATUS(ending.status);
    else
        result.signal = WTERMSIG(ending.status);
    auto set = [&](SandboxOutcome outcome, std::string description, std::string evidence) {
        result.outcome = outcome;
        result.description = std::move(description);
        result.evidence = std::move(evidence);
    };
    if (ending.wallKilled && result.signal == SIGKILL) {
        result.killedBySandbox = true;
        return set(SandboxOutcome::WallTimeLimit,
                   "wall-time limit of " + limitSecondsText(limits.wallSeconds) + " exceeded: killed after " +
                       secondsText(result.wallSeconds),
                   "the sandbox's SIGKILL at the wall-clock limit");
    }
    const std::string cpu_limit =
        "CPU-time limit of " + limitSecondsText(double(limits.cpuSeconds)) + " exceeded: ";
    if (result.signal == SIGXCPU)
        return set(SandboxOutcome::CpuTimeLimit,
                   cpu_limit + "SIGXCPU after " + secondsText(result.cpuSeconds) + " of CPU time", "SIGXCPU");
    if (result.signal == SIGKILL && limits.cpuSeconds > 0 && result.cpuSeconds >= double(limits.cpuSeconds))
        return set(
            SandboxOutcome::CpuTimeLimit,
            cpu_limit + "SIGKILL at the hard limit after " + secondsText(result.cpuSeconds) + " of CPU time",
            "SIGKILL with the CPU time at the limit");
    if (result.signal == SIGXFSZ)
        return set(SandboxOutcome::OutputSizeLimit,
                   "output-size limit of " + formatBytes(limits.fileSizeBytes) + " exceeded: SIGXFSZ",
                   "SIGXFSZ");
    if ((result.signal != 0 || result.exitStatus != 0) && describeFailure(result, limits)) return;
    if (result.signal == SIGKILL)
        return set(
            SandboxOutcome::Signaled,
            endingText(result) + ", not sent by the sandbox: perhaps the kernel's out-of-memory killer", "");
    set(result.signal != 0 ? SandboxOutcome::Signaled : SandboxOutcome::Exited, endingText(result), "");
}

std::string startFailureText(const std::string& program, const StartFailure& failure) {
    return "could not start '" + program + "': " + startStepText(failure.step) + ": " +
           errnoText(failure.error);
}

}  // namespace

std::vector<std::string> defaultSandboxEnvironment(const std::string& home) {
    return {"PATH=/usr/local/bin:/usr/bin:/bin", "HOME=" + home, "TMPDIR=" + home, "LANG=C"};
}

std::string signalDescription(int signal) {
    static constexpr std::pair<int, const char*> kNames[] = {
        {SIGSEGV, "segmentation fault (SIGSEGV)"},
        {SIGABRT, "aborted (SIGABRT)"},
        {SIGBUS, "bus error (SIGBUS)"},
        {SIGFPE, "arithmetic exception (SIGFPE)"},
        {SIGILL, "illegal instruction (SIGILL)"},
        {SIGKILL, "killed (SIGKILL)"},
        {SIGTERM, "terminated (SIGTERM)"},
        {SIGINT, "interrupted (SIGINT)"},
        {SIGHUP, "hangup (SIGHUP)"},
        {SIGQUIT, "quit (SIGQUIT)"},
        {SIGPIPE, "broken pipe (SIGPIPE)"},
        {SIGALRM, "alarm clock (SIGALRM)"},
        {SIGTRAP, "trace trap (SIGTRAP)"},
        {SIGSYS, "bad system call (SIGSYS)"},
        {SIGXCPU, "CPU-time limit exceeded (SIGXCPU)"},
        {SIGXFSZ, "file-size limit exceeded (SIGXFSZ)"},
        {SIGUSR1, "user signal 1 (SIGUSR1)"},
        {SIGUSR2, "user signal 2 (SIGUSR2)"},
    };
    for (const auto& [number, name] : kNames)
        if (number == signal) return name;
    return "signal " + std::to_string(signal);
}

IsolationChoice isolationFor(const std::optional<std::string>& dropToUser) {
    static std::mutex mutex;
    static std::map<std::string, IsolationChoice> known;  // by the user the child runs as ("": the caller)
    const std::string user = dropToUser && geteuid() == 0 ? *dropToUser : "";
    const std::lock_guard lock(mutex);
    auto it = known.find(user);
    if (it == known.end()) it = known.emplace(user, probeIsolation(dropToUser)).first;
    return it->second;
}

size_t userTaskCount(uid_t uid) {
    size_t count = 0;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator("/proc", error)) {
        const std::string name = entry.path().filename().string();
        if (name.empty() ||
            !std::all_of(name.begin(), name.end(), [](char c) { return c >= '0' && c <= '9'; }))
            continue;
        std::ifstream status(entry.path() / "status");
        std::string line;
        long real_uid = -1, threads = 0;
        while (std::getline(status, line)) {
            if (line.rfind("Uid:", 0) == 0) real_uid = std::strtol(line.c_str() + 4, nullptr, 10);
            if (line.rfind("Threads:", 0) == 0) threads = std::strtol(line.c_str() + 8, nullptr, 10);
        }
        if (real_uid == long(uid)) count += size_t(std::max(threads, 1L));
    }
    return count;
}

SandboxResult runSandboxed(const SandboxCommand& command) {
    RASTER_REQUIRE(!command.argv.empty() && !command.argv[0].empty(), InvalidArgument,
                   "the sandboxed command has no program (argv is empty)");
    struct sigaction child_signal {};
    sigaction(SIGCHLD, nullptr, &child_signal);
    RASTER_REQUIRE(child_signal.sa_handler != SIG_IGN && !(child_signal.sa_flags & SA_NOCLDWAIT),
                   InvalidState,
                   "SIGCHLD is ignored in this process: the sandbox could not learn how its child ended");
    requireDirectory(command.workingDirectory, "working directory");
    requireDirectory(command.scratchDirectory, "scratch directory");
    SandboxResult result;
    const RunAs run = resolveUser(command, result.warnings);
    if (run.drop && !command.scratchDirectory.empty()) handOver(command.scratchDirectory, run);
    if (run.uid == 0 && command.limits.processes > 0)
        result.warnings.push_back(
            "RLIMIT_NPROC is not enforced for root: the child runs as root, without a process limit");
    result.uid = run.uid;

    const std::string home = !command.scratchDirectory.empty()   ? command.scratchDirectory
                             : !command.workingDirectory.empty() ? command.workingDirectory
                                                                 : std::filesystem::current_path().string();
    const std::vector<std::string> environment =
        command.environment.value_or(defaultSandboxEnvironment(home));
    const Confinement confinement = confine(command, result.warnings);
    result.isolation = confinement.isolation;
    ChildPlan plan;
    for (const std::string& arg : confinement.argv) plan.argv.push_back(const_cast<char*>(arg.c_str()));
    for (const std::string& variable : environment) plan.envp.push_back(const_cast<char*>(variable.c_str()));
    plan.argv.push_back(nullptr);
    plan.envp.push_back(nullptr);
    plan.directory = command.workingDirectory.empty() ? nullptr : command.workingDirectory.c_str();
    plan.limits = planLimits(command.limits);
    plan.landlockRuleset = confinement.ruleset.get();
    std::tie(plan.drop, plan.uid, plan.gid) = std::tuple(run.drop, run.uid, run.gid);

    Pipe out = makePipe("standard output"), err = makePipe("standard error"),
         report = makePipe("start report");
    Fd null(::open("/dev/null", O_RDONLY | O_CLOEXEC));
    if (null.get() < 0)
        throw Error(ErrorCode::InvalidState, "cannot open /dev/null for the sandbox: " + errnoText(errno));
    std::tie(plan.stdinFd, plan.stdoutFd, plan.stderrFd, plan.reportFd) =
        std::tuple(null.get(), out.write.get(), err.write.get(), report.write.get());
    plan.parent = getpid();

    const auto start = Clock::now();
    const pid_t pid = fork();
    if (pid == 0) runChild(plan);
    if (pid < 0)
        throw Error(ErrorCode::InvalidState,
                    "cannot start a process for the sandbox: fork: " + errnoText(errno));
    setpgid(pid, pid);  // the child does the same: whichever comes first
    out.write.reset(), err.write.reset(), report.write.reset(), null.reset();

    Stream so{out.read.release(), command.limits.stdoutBytes},
        se{err.read.release(), command.limits.stderrBytes}, sr{report.read.release(), sizeof(StartFailure)};
    Ending ending = watch(pid, {&so, &se, &sr}, command.limits.wallSeconds, start);
    // bwrap exits with 128 + N when its child was killed by signal N: read back as that signal.
    const int status = WIFEXITED(ending.status) ? WEXITSTATUS(ending.status) : 0;
    if (confinement.isolation == Isolation::Bubblewrap && status > 128 && status < 128 + NSIG)
        ending.status = status - 128;
    result.pid = pid;
    result.wallSeconds = ending.wallSeconds;
    const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    result.cpuSeconds = seconds(ending.usage.ru_utime) + seconds(ending.usage.ru_stime);
    result.peakRssBytes = uint64_t(ending.usage.ru_maxrss) * 1024;  // Linux counts it in KiB
    result.stdoutText = std::move(so.kept), result.stderrText = std::move(se.kept);
    result.stdoutTotalBytes = so.total, result.stderrTotalBytes = se.total;
    result.stdoutTruncated = so.total > result.stdoutText.size();
    result.stderrTruncated = se.total > result.stderrText.size();
    if (sr.kept.size() == sizeof(StartFailure)) {
        StartFailure failure;
        std::memcpy(&failure, sr.kept.data(), sizeof failure);
        result.outcome = SandboxOutcome::StartFailed;
        result.description = startFailureText(command.argv[0], failure);
        if (WIFEXITED(ending.status)) result.exitStatus = WEXITSTATUS(ending.status);
        return result;
    }
    describe(result, ending, command.limits);
    return result;
}

}  // namespace raster::grade
