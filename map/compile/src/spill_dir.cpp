// SPDX-License-Identifier: Apache-2.0
#include "spill_dir.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "navmap/map/compile/spill_file.h"

namespace navmap::map::detail {

namespace {

namespace fs = std::filesystem;

constexpr const char* kPrefix = "navmap-spill-";
constexpr std::size_t kMaxOwnerBytes = 256;

std::string firstLine(const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);
    return line;
}

std::string bootId() { return firstLine("/proc/sys/kernel/random/boot_id"); }

/// Field 22 of /proc/<pid>/stat: the start time in clock ticks after boot; nullopt when unreadable.
std::optional<std::uint64_t> startTicks(pid_t pid) {
    const std::string stat = firstLine("/proc/" + std::to_string(pid) + "/stat");
    const auto paren = stat.rfind(')');  // the command name may hold spaces and parentheses
    if (paren == std::string::npos) return std::nullopt;
    std::istringstream fields(stat.substr(paren + 1));
    std::string field;
    for (int i = 3; i <= 22; ++i) {  // field 3, the state, follows the name
        if (!(fields >> field)) return std::nullopt;
    }
    char* end = nullptr;
    const unsigned long long v = std::strtoull(field.c_str(), &end, 10);
    if (end == field.c_str() || *end != '\0') return std::nullopt;
    return v;
}

bool processGone(pid_t pid) { return ::kill(pid, 0) != 0 && errno == ESRCH; }

std::uint64_t bytesUnder(const fs::path& dir) {
    std::uint64_t bytes = 0;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code size_ec;
        if (it->is_regular_file(size_ec)) bytes += it->file_size(size_ec);
    }
    return bytes;
}

}  // namespace

SpillOwner SpillOwner::self() {
    SpillOwner o;
    o.pid = ::getpid();
    o.start_ticks = startTicks(o.pid).value_or(0);
    o.boot_id = bootId();
    return o;
}

std::optional<SpillOwner> SpillOwner::parse(const std::string& text) {
    std::istringstream in(text);
    long long pid = 0;
    SpillOwner o;
    if (!(in >> pid >> o.start_ticks) || pid <= 0 || pid > 0x7fffffff) return std::nullopt;
    o.pid = static_cast<pid_t>(pid);
    in >> o.boot_id;  // may be missing where /proc had none
    return o;
}

std::string SpillOwner::text() const {
    return std::to_string(pid) + " " + std::to_string(start_ticks) + " " + boot_id + "\n";
}

bool SpillOwner::mayBeAlive() const {
    if (!boot_id.empty()) {
        const std::string now = bootId();
        if (!now.empty() && now != boot_id) return false;  // recorded before the last boot
    }
    if (processGone(pid)) return false;
    const auto start = startTicks(pid);
    if (!start) return !processGone(pid);  // it may have ended just now; else /proc does not tell
    return *start == start_ticks;          // another start time: the pid was reused
}

std::size_t SpillDir::removeStale(const fs::path& parent, const std::function<void(const std::string&)>& log) {
    std::size_t removed = 0;
    std::error_code ec;
    for (fs::directory_iterator it(parent.empty() ? fs::path(".") : parent, ec), end; !ec && it != end;
         it.increment(ec)) {
        const fs::path dir = it->path();
        if (dir.filename().string().rfind(kPrefix, 0) != 0) continue;
        struct stat st {};
        // Only real folders of this user: never through a link, never another user's folder.
        if (::lstat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid()) continue;
        const fs::path owner_file = dir / "owner";
        const int fd = ::open(owner_file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
        if (fd < 0) continue;  // being made, or not ours to judge
        char buf[kMaxOwnerBytes];
        const ssize_t n = ::read(fd, buf, sizeof buf);
        const auto owner = n > 0 ? SpillOwner::parse(std::string(buf, static_cast<std::size_t>(n))) : std::nullopt;
        // A lock held: the owner runs, whatever its pid says here (another pid namespace).
        const bool stale =
            owner && !owner->mayBeAlive() && !(::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK);
        if (stale) {
            const std::uint64_t bytes = bytesUnder(dir);
            std::error_code rm;
            fs::remove_all(dir, rm);
            if (rm) {
                if (log) log("warning: cannot remove the stale spill folder " + dir.string() + ": " + rm.message());
            } else {
                ++removed;
                if (log)
                    log("removed the spill folder " + dir.string() + " of process " + std::to_string(owner->pid) +
                        ", which is gone (" + std::to_string(bytes) + " bytes)");
            }
        }
        ::close(fd);
    }
    return removed;
}

SpillDir::SpillDir(const fs::path& parent, std::function<void(const std::string&)> log) : m_log(std::move(log)) {
    removeStale(parent, m_log);
    const std::string pattern = (parent.empty() ? fs::path(".") : parent) / (std::string(kPrefix) + "XXXXXX");
    std::string name = pattern;  // mkdtemp() fills the Xs in, even when it fails
    if (::mkdtemp(name.data()) == nullptr) throw SpillError("mkdtemp(" + pattern + "): " + std::strerror(errno));
    m_path = name;
    // The owner file, locked before it gets its name: a folder's owner file is never seen unlocked
    // while its owner runs.
    const fs::path temp = m_path / "owner.new";
    const std::string text = SpillOwner::self().text();
    const char* failed = nullptr;
    m_owner_fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (m_owner_fd < 0) {
        failed = "open";
    } else {
        (void)::flock(m_owner_fd, LOCK_EX);  // a file system without flock: the pid and start time still tell
        if (::write(m_owner_fd, text.data(), text.size()) != static_cast<ssize_t>(text.size())) {
            failed = "write";
        } else if (::rename(temp.c_str(), (m_path / "owner").c_str()) != 0) {
            failed = "rename";
        }
    }
    if (failed) {
        const std::string error = std::string(failed) + "(" + temp.string() + "): " + std::strerror(errno);
        if (m_owner_fd >= 0) ::close(m_owner_fd);
        std::error_code ec;
        fs::remove_all(m_path, ec);
        throw SpillError(error);
    }
}

SpillDir::~SpillDir() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
    if (ec && m_log) m_log("warning: cannot remove " + m_path.string() + ": " + ec.message());
    if (m_owner_fd >= 0) ::close(m_owner_fd);
}

}  // namespace navmap::map::detail
