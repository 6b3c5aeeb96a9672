// Landlock's rulesets and bubblewrap's command lines for the sandbox (isolation.hpp says what each
// guarantees).
#include "grade/isolation.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>

#include "raster/check.hpp"

namespace raster::grade {
namespace {

// Landlock's user-space interface (linux/landlock.h), written out here: the kernel's interface is
// stable, and Debian 12's headers (Linux 6.1) lack what ABI 3 and later added.
constexpr uint32_t kCreateRulesetVersion = 1u << 0;  // LANDLOCK_CREATE_RULESET_VERSION
constexpr int kRulePathBeneath = 1;                  // LANDLOCK_RULE_PATH_BENEATH
// LANDLOCK_ACCESS_FS_*: the rights on files (the first three, and write, truncate and device ioctl,
// are the ones a rule on a file may hold); the rest apply to a folder's entries.
constexpr uint64_t kExecute = 1u << 0, kWriteFile = 1u << 1, kReadFile = 1u << 2, kReadDir = 1u << 3;
constexpr uint64_t kAbi1Rights = (1u << 13) - 1;  // execute .. make_sym
constexpr uint64_t kRefer = 1u << 13;             // ABI 2: link and rename across folders
constexpr uint64_t kTruncate = 1u << 14;          // ABI 3
constexpr uint64_t kIoctlDev = 1u << 15;          // ABI 5
constexpr uint64_t kFileRights = kExecute | kWriteFile | kReadFile | kTruncate | kIoctlDev;
constexpr uint64_t kReadRights = kExecute | kReadFile | kReadDir;
// LANDLOCK_ACCESS_NET_BIND_TCP, _CONNECT_TCP (ABI 4); LANDLOCK_SCOPE_ABSTRACT_UNIX_SOCKET, _SIGNAL (ABI 6).
constexpr uint64_t kNetRights = (1u << 0) | (1u << 1);
constexpr uint64_t kScopes = (1u << 0) | (1u << 1);

struct RulesetAttr {  // struct landlock_ruleset_attr; its size tells the kernel which fields it holds
    uint64_t handledAccessFs = 0, handledAccessNet = 0, scoped = 0;
};
struct PathBeneathAttr {  // struct landlock_path_beneath_attr, packed as the kernel's
    uint64_t allowedAccess;
    int32_t parentFd;
} __attribute__((packed));

uint64_t handledFsRights(int abi) {
    uint64_t rights = kAbi1Rights;
    if (abi >= 2) rights |= kRefer;
    if (abi >= 3) rights |= kTruncate;
    if (abi >= 5) rights |= kIoctlDev;
    return rights;
}

std::string landlockErrorText(int error) {
    std::string text = std::string("landlock_create_ruleset: ") + std::strerror(error);
    if (error == ENOSYS) return text + ": this kernel has no Landlock (Linux 5.13 and later have it)";
    if (error == EOPNOTSUPP)
        return text + ": Landlock is built in but not enabled (lsm= on the kernel's command line)";
    if (error == EPERM) return text + ": refused, as a container's seccomp profile does";
    return text;
}

void addRule(int ruleset, const std::string& path, uint64_t rights, uint64_t handled) {
    const int fd = ::open(path.c_str(), O_PATH | O_CLOEXEC);
    if (fd < 0) return;  // a path this machine does not have: nothing to allow
    struct stat info {};
    if (fstat(fd, &info) == 0 && !S_ISDIR(info.st_mode)) rights &= kFileRights;
    const PathBeneathAttr rule{rights & handled, fd};
    const long added = syscall(SYS_landlock_add_rule, ruleset, kRulePathBeneath, &rule, 0);
    const int error = errno;
    ::close(fd);
    if (added != 0)
        throw Error(ErrorCode::InvalidState, "landlock_add_rule for '" + path + "': " + std::strerror(error));
}

void addBinds(std::vector<std::string>& out, const std::vector<std::string>& paths, const char* bind) {
    for (const std::string& path : paths) out.insert(out.end(), {bind, path, path});
}

}  // namespace

const char* isolationName(Isolation isolation) {
    switch (isolation) {
        case Isolation::Auto:
            return "auto";
        case Isolation::Landlock:
            return "landlock";
        case Isolation::Bubblewrap:
            return "bubblewrap";
        case Isolation::None:
            return "none";
    }
    return "none";
}

Isolation parseIsolation(const std::string& name) {
    for (Isolation i : {Isolation::Auto, Isolation::Landlock, Isolation::Bubblewrap, Isolation::None})
        if (name == isolationName(i)) return i;
    if (name == "bwrap") return Isolation::Bubblewrap;
    throw Error(ErrorCode::InvalidArgument,
                "isolation '" + name + "': one of auto, landlock, bubblewrap (or bwrap), none");
}

int landlockAbi(std::string* why) {
    const long abi = syscall(SYS_landlock_create_ruleset, nullptr, 0, kCreateRulesetVersion);
    if (abi > 0) return int(abi);
    if (why) *why = landlockErrorText(errno);
    return 0;
}

std::string findBubblewrap() {
    for (const char* folder : {"/usr/local/bin", "/usr/bin", "/bin"}) {
        const std::string path = std::string(folder) + "/bwrap";
        if (access(path.c_str(), X_OK) == 0) return path;
    }
    return "";
}

int makeLandlockRuleset(const FileAccess& access, int abi) {
    RASTER_REQUIRE(abi >= 1, InvalidState, "Landlock is not available: no ruleset can be made");
    RulesetAttr attr;
    attr.handledAccessFs = handledFsRights(abi);
    size_t size = sizeof(uint64_t);
    if (abi >= 4) attr.handledAccessNet = kNetRights, size = 2 * sizeof(uint64_t);
    if (abi >= 6) attr.scoped = kScopes, size = sizeof attr;
    const int ruleset = int(syscall(SYS_landlock_create_ruleset, &attr, size, 0));
    if (ruleset < 0) throw Error(ErrorCode::InvalidState, landlockErrorText(errno));
    try {
        for (const std::string& path : access.readable)
            addRule(ruleset, path, kReadRights, attr.handledAccessFs);
        for (const std::string& path : access.writable)
            addRule(ruleset, path, attr.handledAccessFs, attr.handledAccessFs);
    } catch (...) {
        ::close(ruleset);
        throw;
    }
    return ruleset;
}

int applyLandlock(int ruleset) {
    if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) return -1;
    return int(syscall(SYS_landlock_restrict_self, ruleset, 0));
}

std::vector<std::string> bubblewrapArgv(const std::string& bwrap, const FileAccess& access,
                                        const std::string& directory, const std::vector<std::string>& argv) {
    // No --new-session nor --unshare-pid: the child stays in the sandbox's process group, which the
    // sandbox kills as a whole. --die-with-parent: bwrap's own child dies with it.
    std::vector<std::string> out = {
        bwrap, "--die-with-parent", "--unshare-net", "--unshare-ipc", "--unshare-uts", "--dev", "/dev"};
    addBinds(out, access.readable, "--ro-bind-try");
    addBinds(out, access.writable, "--bind-try");
    if (!directory.empty()) out.insert(out.end(), {"--chdir", directory});
    out.push_back("--");
    out.insert(out.end(), argv.begin(), argv.end());
    return out;
}

}  // namespace raster::grade
