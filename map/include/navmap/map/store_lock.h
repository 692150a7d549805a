// SPDX-License-Identifier: Apache-2.0
#pragma once
// StoreLock: the one writer of a tile store. An exclusive flock() on "<store>.lock" is held from
// before the compile reads its input until the store is renamed into place, so a second
// navmap-compile to the same --out fails at once naming the first one's pid instead of racing it
// for the rename. The lock file is opened without following symbolic links and removed on release.

#include <filesystem>

namespace navmap::map {

class StoreLock {
public:
    /// Checks that the store's folder exists (it is never created), opens "<store>.lock"
    /// (O_CREAT | O_NOFOLLOW: a symbolic link, or anything but a regular file with one link, is
    /// refused), takes flock(LOCK_EX | LOCK_NB) and writes this process's pid into it. Throws
    /// StoreError: "<store> is being written by another process (pid N)", "<store>: directory
    /// <dir> does not exist", "<store>.lock: is a symbolic link; refusing to follow it", or a
    /// failed call naming the file.
    explicit StoreLock(const std::filesystem::path& store);
    /// Removes the lock file and releases the lock. Never throws.
    ~StoreLock();
    StoreLock(StoreLock&& other) noexcept;
    StoreLock& operator=(StoreLock&& other) = delete;
    StoreLock(const StoreLock&) = delete;
    StoreLock& operator=(const StoreLock&) = delete;

    /// The store this lock is for.
    [[nodiscard]] const std::filesystem::path& store() const { return m_store; }
    /// "<store>.lock".
    [[nodiscard]] const std::filesystem::path& lockPath() const { return m_lock_path; }

private:
    std::filesystem::path m_store;
    std::filesystem::path m_lock_path;
    int m_fd = -1;
};

}  // namespace navmap::map
