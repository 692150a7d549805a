// SPDX-License-Identifier: Apache-2.0
#pragma once
// UniqueFd: the one owner of a file descriptor (socket, eventfd, memfd, signalfd). Move-only;
// the destructor and reset() close it exactly once; release() hands it on without closing.

namespace navmap::ipc::net {

/// Owns a descriptor (-1: none) and closes it on destruction. Not thread-safe: one owner thread.
class UniqueFd {
public:
    UniqueFd() = default;
    explicit UniqueFd(int fd) noexcept : m_fd(fd) {}
    ~UniqueFd();
    UniqueFd(UniqueFd&& other) noexcept : m_fd(other.release()) {}
    UniqueFd& operator=(UniqueFd&& other) noexcept;
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;

    [[nodiscard]] int get() const noexcept { return m_fd; }
    [[nodiscard]] bool valid() const noexcept { return m_fd >= 0; }
    /// Gives up ownership without closing; the caller closes the returned descriptor.
    [[nodiscard]] int release() noexcept;
    /// Closes the owned descriptor (if any) and owns `fd` instead.
    void reset(int fd = -1) noexcept;

private:
    int m_fd = -1;
};

}  // namespace navmap::ipc::net
