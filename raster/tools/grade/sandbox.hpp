// The sandbox of raster grade (docs/GRADING.md): runs one command of a grading run — a submission's
// build, the render of its scenes — in a child process under limits, and says what became of it in
// words a grader prints.
//
//   raster::grade::SandboxCommand command;
//   command.argv = {"cmake", "--build", "build", "-j1"};
//   command.workingDirectory = command.scratchDirectory = "/tmp/grade/alice";
//   command.limits.wallSeconds = 300;
//   const raster::grade::SandboxResult result = raster::grade::runSandboxed(command);
//   if (!result.succeeded()) std::printf("build %s\n", result.description.c_str());
//     // "build wall-time limit of 300 s exceeded: killed after 300.01 s"
//
// What the child gets, set between fork and exec (Linux):
//  - its own process group (setpgid), so that the sandbox can kill it and everything it started at
//    once (SIGKILL to the group) when the wall-clock limit passes, and when the child itself ends:
//    nothing it left running in the background outlives runSandboxed;
//  - the limits of SandboxLimits as rlimits, and no core dumps (RLIMIT_CORE 0);
//  - standard input from /dev/null, standard output and error into pipes that the parent reads while
//    it waits (both at once, so a child that fills one is never blocked), every other descriptor
//    closed;
//  - where the caller is root (as on Gradescope), the identity of an unprivileged user (`nobody` by
//    default): setgroups, setgid, setuid, in that order, after the limits are set and before exec.
//    Root may write anywhere and RLIMIT_NPROC does not apply to it, so a submission must not run as
//    root. The scratch directory is handed to that user (chown, recursively) beforehand;
//  - an environment of its own: PATH, HOME, TMPDIR and LANG=C only (defaultSandboxEnvironment),
//    unless the command gives one;
//  - death with its parent (PR_SET_PDEATHSIG SIGKILL), so that a grader killed mid-run leaves no
//    submission running;
//  - with `files` set, only those files (isolation.hpp): Landlock where the kernel has it, else
//    bubblewrap where it runs, else nothing beyond the user's permissions (result.isolation and
//    result.warnings say which held).
//
// What it cannot do: a process that leaves the child's process group (setsid, setpgid) escapes the
// group's kill, as it would with `timeout`; the sandbox stops reading its output 0.25 s after the
// child ends, so it cannot hold runSandboxed up, but it may live on. Without `files`, or where neither
// Landlock nor bubblewrap is available, there is no file-system isolation beyond the user's
// permissions.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "grade/isolation.hpp"

namespace raster::grade {

constexpr uint64_t kMiB = uint64_t(1) << 20;
constexpr uint64_t kGiB = uint64_t(1) << 30;

// The limits of one run. A limit of 0 means none (for fileSizeBytes too: 0 is not "no files").
struct SandboxLimits {
    // Seconds of wall-clock time from the start until the sandbox kills the child's process group
    // (SIGKILL). Enforced by the parent, so it holds whatever the child does (sleeps, blocks, forks).
    double wallSeconds = 120;
    // Seconds of CPU time (user + system) for each process (RLIMIT_CPU is per process: every compiler
    // a build starts has its own; the wall-clock limit bounds the sum). At the limit the kernel sends
    // SIGXCPU, and SIGKILL a second later (the hard limit) to a process that ignores it.
    uint64_t cpuSeconds = 120;
    // Bytes of address space for each process (RLIMIT_AS): mappings, not resident memory, so thread
    // stacks (8 MiB each) and reserved but untouched memory count. An allocation past it fails
    // (malloc returns null, new throws std::bad_alloc): the process is not killed by the kernel.
    uint64_t addressSpaceBytes = 4 * kGiB;
    // Processes and threads (RLIMIT_NPROC). The kernel counts every task of the child's real user id
    // on the machine, not only the child's: as a non-root caller that is the caller's own user, so pass
    // userTaskCount(getuid()) + N; concurrent sandboxes that drop to the same user share the count.
    // Not enforced for root (result.warnings says so when the child runs as root). A fork past it fails
    // with EAGAIN, which the child sees as an error of its own. raster's thread pool counts too.
    uint64_t processes = 256;
    // Bytes the child may write to one file (RLIMIT_FSIZE); a write past it raises SIGXFSZ (or fails
    // with EFBIG where the child ignores that signal). Pipes are not files: see the next two.
    uint64_t fileSizeBytes = 256 * kMiB;
    // Bytes of standard output and of standard error kept: the first N, the rest read and dropped
    // (result.stdoutTruncated, stdoutTotalBytes). 0 keeps nothing.
    size_t stdoutBytes = 1 * kMiB;
    size_t stderrBytes = 1 * kMiB;
};

struct SandboxCommand {
    // The program and its arguments, run with execvp (no shell): argv[0] is looked up on the PATH of
    // the child's environment. Must not be empty.
    std::vector<std::string> argv;
    // Where the child starts; empty: the caller's current directory. Must exist.
    std::string workingDirectory;
    // The directory the child writes to (its build folder, its images): when the child drops to
    // another user, it and everything below it are given to that user first (lchown, recursively;
    // links are not followed). Also HOME and TMPDIR of the default environment. Empty: none.
    std::string scratchDirectory;
    // "NAME=value" entries, the child's whole environment; nullopt: defaultSandboxEnvironment(home),
    // home being the scratch directory, else the working directory.
    std::optional<std::vector<std::string>> environment;
    // The user the child runs as when the caller is root (euid 0), by name (getpwnam: its uid and its
    // primary gid, the only group). nullopt: never drop (the child runs as the caller). A caller that
    // is not root cannot change user and ignores it.
    std::optional<std::string> dropToUser = "nobody";
    SandboxLimits limits;
    // The files the child may open (isolation.hpp); nullopt: whatever its user may.
    std::optional<FileAccess> files;
    // How `files` is enforced: Auto, the best this machine has (isolationFor); Landlock or Bubblewrap,
    // that one or an Error(InvalidState) saying why not; None, not at all (a warning says so).
    Isolation isolation = Isolation::Auto;
};

// What ended the child, most specific first: a limit the sandbox can tell, else how it ended.
enum class SandboxOutcome {
    Exited,           // exited by itself (exitStatus, 0 = success) with no sign of a limit
    Signaled,         // killed by a signal no limit accounts for (a crash: SIGSEGV, SIGABRT, ...)
    WallTimeLimit,    // still running at limits.wallSeconds: the sandbox killed its process group
    CpuTimeLimit,     // SIGXCPU, or SIGKILL once its CPU time had reached limits.cpuSeconds
    MemoryLimit,      // evidence of a failed allocation (see `evidence`): never certain, see below
    OutputSizeLimit,  // SIGXFSZ, or a failure whose stderr says "File too large" (EFBIG)
    ProcessLimit,     // a failure whose stderr says a fork or thread failed (EAGAIN), under limits.processes
    StartFailed,      // never ran: the program was not found, or the set-up before exec failed
};

// How the sandbox tells the limits that the kernel does not report as such (MemoryLimit,
// ProcessLimit): only when the child failed (nonzero status or a signal), from what it printed,
// since an allocation or a fork that fails is an error returned to the child, not a signal:
//  - memory: its captured stderr holds "bad_alloc" (libstdc++'s std::terminate message), "out of
//    memory" (raster's Error(OutOfMemory), GCC's cc1plus), "OutOfMemory", "Cannot allocate memory"
//    (ENOMEM) or "memory exhausted" (any case); or it died of SIGSEGV, SIGBUS or SIGABRT with a peak
//    resident size of at least 75 % of limits.addressSpaceBytes (what a program that does not check
//    malloc's result does). A crash at a smaller size after a failed malloc reads as a plain crash,
//    and a program that prints "out of memory" for another reason reads as this limit.
//  - processes: its stderr holds "Resource temporarily unavailable" (EAGAIN, from fork, clone or
//    std::thread), "Cannot fork" (dash) or "fork: retry" (bash), and limits.processes was set.
// A SIGKILL that the sandbox did not send and that no CPU limit explains is reported as Signaled, and
// the description says it may be the kernel's out-of-memory killer (the machine's or a container's
// memory, not RLIMIT_AS).
struct SandboxResult {
    SandboxOutcome outcome = SandboxOutcome::StartFailed;
    // One line for a grader to print: "exited with status 3", "killed by signal 11: segmentation
    // fault (SIGSEGV)", "wall-time limit of 1 s exceeded: killed after 1.00 s", "CPU-time limit of 1 s
    // exceeded: SIGXCPU after 1.00 s of CPU time", "memory limit of 64.0 MiB (67108864 bytes)
    // exceeded: stderr says "std::bad_alloc"; killed by signal 6: aborted (SIGABRT)", "could not start
    // 'foo': execvp: No such file or directory".
    std::string description;
    // How a limit was told ("SIGXCPU", "stderr says \"std::bad_alloc\""); empty for Exited, Signaled.
    std::string evidence;
    std::optional<int> exitStatus;  // the status it exited with, if it exited
    int signal = 0;                 // the signal that killed it, 0 if it exited
    bool killedBySandbox = false;   // the wall-clock limit's SIGKILL

    double wallSeconds = 0;     // from fork to the child's end
    double cpuSeconds = 0;      // user + system, of the child and the descendants it waited for (wait4)
    uint64_t peakRssBytes = 0;  // the largest resident size of the child or of one such descendant

    std::string stdoutText, stderrText;                   // the first limits.stdoutBytes / stderrBytes
    uint64_t stdoutTotalBytes = 0, stderrTotalBytes = 0;  // all that was written, kept or not
    bool stdoutTruncated = false, stderrTruncated = false;

    pid_t pid = 0;  // the child's process id, also its process group's id (all ended by now)
    uid_t uid = 0;  // the user id it ran as
    // Limits that could not apply, e.g. "RLIMIT_NPROC is not enforced for root: the child ran as root",
    // or "no file-system isolation: Landlock unavailable (...); bubblewrap unavailable (...)".
    std::vector<std::string> warnings;
    // How `files` held: Landlock, Bubblewrap, or None (also when no `files` were given).
    Isolation isolation = Isolation::None;

    bool succeeded() const { return outcome == SandboxOutcome::Exited && exitStatus == 0; }
};

// Runs `command` as described above and returns once the child has ended and been reaped and its
// process group has been killed. Safe to call from several threads at once (each child gets only its
// own pipes), provided no thread of the caller reaps any child (waitpid(-1)): that would take the
// child's status (the result then says so, with no exitStatus). Throws raster::Error: InvalidArgument
// for an empty argv or a user to drop to that does not exist, BadFile for a working or scratch
// directory that does not exist or cannot be handed over, InvalidState when no pipe or process can be
// made or when SIGCHLD is ignored (the kernel would then reap the child before its status is read).
SandboxResult runSandboxed(const SandboxCommand& command);

// PATH=/usr/local/bin:/usr/bin:/bin, HOME=home, TMPDIR=home, LANG=C.
std::vector<std::string> defaultSandboxEnvironment(const std::string& home);

// "segmentation fault (SIGSEGV)", "aborted (SIGABRT)", ...; "signal 42" for one without a name.
std::string signalDescription(int signal);

// The processes and threads whose real user id is `uid` (from /proc): what RLIMIT_NPROC counts.
size_t userTaskCount(uid_t uid);

// What Isolation::Auto chooses for a child that runs as `dropToUser` (as runSandboxed resolves it) and
// why (isolation.hpp): Landlock where the kernel has it; else bubblewrap where a bwrap on the PATH
// runs as that user (tried once: `bwrap ... true`); else None, the description naming why neither:
// "Landlock ABI 7", "bubblewrap (/usr/bin/bwrap)", "no file-system isolation: Landlock unavailable
// (landlock_create_ruleset: Function not implemented: ...); bubblewrap unavailable (no bwrap on the
// PATH)". Probed once for each user and kept.
IsolationChoice isolationFor(const std::optional<std::string>& dropToUser);

}  // namespace raster::grade
