// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/store_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>

#include "navmap/map/store_info.h"

namespace navmap::map {

namespace {

std::string sysError(const char* call, const std::filesystem::path& object) {
    return std::string(call) + "(" + object.string() + "): " + std::strerror(errno);
}

/// The pid a lock holder wrote into its lock file; 0 when it cannot be read (yet).
long holderPid(int fd) {
    // The holder writes its pid right after taking the lock: give it a moment.
    for (int attempt = 0; attempt < 20; ++attempt) {
        char buf[32] = {};
        const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
        long pid = 0;
        if (n > 0) {
            const auto [end, ec] = std::from_chars(buf, buf + n, pid);
            if (ec == std::errc{} && end != buf && pid > 0) return pid;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return 0;
}

}  // namespace

StoreLock::StoreLock(const std::filesystem::path& store) : m_store(store), m_lock_path(store.string() + ".lock") {
    // A missing folder is an error, never created: a typo in --out must not grow a tree.
    const std::filesystem::path dir = store.has_parent_path() ? store.parent_path() : std::filesystem::path(".");
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0) {
        if (errno == ENOENT) throw StoreError(store.string() + ": directory " + dir.string() + " does not exist");
        throw StoreError(sysError("stat", dir));
    }
    if (!S_ISDIR(st.st_mode)) throw StoreError(store.string() + ": " + dir.string() + " is not a directory");

    // The holder removes the lock file on release; whoever locked a file that was removed
    // meanwhile holds a lock nobody else sees, so it checks the name still leads to its file.
    for (int attempt = 0;; ++attempt) {
        const int fd = ::open(m_lock_path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd < 0) {
            if (errno == ELOOP) throw StoreError(m_lock_path.string() + ": is a symbolic link; refusing to follow it");
            throw StoreError(sysError("open", m_lock_path));
        }
        struct stat fst {};
        if (::fstat(fd, &fst) != 0) {
            const std::string err = sysError("fstat", m_lock_path);
            ::close(fd);
            throw StoreError(err);
        }
        if (!S_ISREG(fst.st_mode) || fst.st_nlink > 1) {
            ::close(fd);
            throw StoreError(m_lock_path.string() + ": not a regular file with a single link; refusing to use it");
        }
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            if (errno == EWOULDBLOCK) {
                const long pid = holderPid(fd);
                ::close(fd);
                throw StoreError(store.string() + " is being written by another process (pid " +
                                 (pid > 0 ? std::to_string(pid) : std::string("unknown")) + ")");
            }
            const std::string err = sysError("flock", m_lock_path);
            ::close(fd);
            throw StoreError(err);
        }
        struct stat now {};
        if (::lstat(m_lock_path.c_str(), &now) == 0 && now.st_dev == fst.st_dev && now.st_ino == fst.st_ino) {
            m_fd = fd;
            break;
        }
        ::close(fd);  // released and removed by its previous holder meanwhile: take the new one
        if (attempt >= 100) throw StoreError(m_lock_path.string() + ": keeps being replaced; cannot lock it");
    }
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(m_fd, 0) != 0 || ::pwrite(m_fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
        const std::string err = sysError("write", m_lock_path);
        ::unlink(m_lock_path.c_str());
        ::close(m_fd);
        m_fd = -1;
        throw StoreError(err);
    }
}

StoreLock::StoreLock(StoreLock&& other) noexcept
    : m_store(std::move(other.m_store)), m_lock_path(std::move(other.m_lock_path)), m_fd(other.m_fd) {
    other.m_fd = -1;
}

StoreLock::~StoreLock() {
    if (m_fd < 0) return;
    // Removed while still locked, so no other writer can be holding the same name.
    ::unlink(m_lock_path.c_str());
    ::close(m_fd);
}

}  // namespace navmap::map
