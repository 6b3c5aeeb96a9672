// The file-system isolation of a sandboxed command (sandbox.hpp, SandboxCommand::files): the files the
// child may open, enforced by the kernel without privileges where this machine allows it.
//
//  - Landlock (Linux 5.13 and later, where the kernel enables it; Debian 12's and Ubuntu 22.04's do):
//    the child restricts itself between fork and exec (prctl(PR_SET_NO_NEW_PRIVS), then
//    landlock_restrict_self) with a ruleset the parent made: read and execute beneath each readable
//    path, everything beneath each writable one, nothing elsewhere (open, execve, mkdir... fail with
//    EACCES). From Landlock ABI 4 no TCP bind or connect; from ABI 6 no signal to, and no abstract Unix
//    socket of, a process outside the sandbox. The restriction is inherited by everything the child
//    starts and cannot be lifted. Not covered: a file's metadata (stat, access: a path's existence
//    shows), and the descriptors the child is given (its standard streams).
//  - bubblewrap (`bwrap`, Debian's bubblewrap; not root, it needs unprivileged user namespaces): the
//    child runs in a mount namespace of its own that holds the readable paths (read-only), the
//    writable ones and a minimal /dev, and no network. A file outside does not exist there (ENOENT).
//    bwrap reports a child killed by signal N as exit status 128 + N: the sandbox reads it back as
//    the signal, so a program that exits with such a status itself reads as killed.
//  - none: the user's permissions only. The result says so, and why the others were not available.
//
// Isolation::Auto picks Landlock, else bubblewrap if a bwrap on the PATH runs (tried once, as the
// user the child runs as), else none: sandbox.hpp's isolationFor says which and why.
#pragma once

#include <string>
#include <vector>

namespace raster::grade {

enum class Isolation { Auto, Landlock, Bubblewrap, None };

// "auto", "landlock", "bubblewrap", "none"; parseIsolation takes the same words (and "bwrap") and
// throws Error(InvalidArgument) naming the others for any other.
const char* isolationName(Isolation isolation);
Isolation parseIsolation(const std::string& name);

// The paths a child may reach, each a file or a folder (a folder: everything beneath it). Paths that
// do not exist are left out. Symbolic links are followed (a rule on /lib, a link to usr/lib, is a
// rule on /usr/lib).
struct FileAccess {
    std::vector<std::string> readable;  // read and execute
    std::vector<std::string> writable;  // read, execute, write, create, remove, rename
};

// What Isolation::Auto chose and why (sandbox.hpp's isolationFor).
struct IsolationChoice {
    Isolation isolation = Isolation::None;
    std::string description;
};

// The Landlock ABI version of this kernel (1 and up), or 0 with `why` set.
int landlockAbi(std::string* why = nullptr);

// The bwrap program on PATH=/usr/local/bin:/usr/bin:/bin, or "" when there is none.
std::string findBubblewrap();

// A Landlock ruleset (a file descriptor, close-on-exec) for `access` at `abi`, to be applied in the
// child by applyLandlock; throws Error(InvalidState) naming the call that failed.
int makeLandlockRuleset(const FileAccess& access, int abi);

// In the child between fork and exec (async-signal-safe: no allocation): no new privileges, then the
// ruleset. Returns 0, or -1 with errno set.
int applyLandlock(int ruleset);

// bwrap's command line for `argv` with `access`, entering `directory` (empty: none), ready for exec.
std::vector<std::string> bubblewrapArgv(const std::string& bwrap, const FileAccess& access,
                                        const std::string& directory, const std::vector<std::string>& argv);

}  // namespace raster::grade
