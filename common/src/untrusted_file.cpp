// SPDX-License-Identifier: Apache-2.0
#include "navmap/common/untrusted_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

namespace navmap {

namespace {

// What a file that is not regular is, for the error.
const char* fileTypeName(mode_t mode) {
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a plain file";
}

// "4 MiB" when a whole number of KiB, MiB or GiB, else "<n> bytes".
std::string bytesText(std::uint64_t bytes) {
    static constexpr const char* kUnits[] = {"GiB", "MiB", "KiB"};
    for (int i = 0; i < 3; ++i) {
        const std::uint64_t unit = std::uint64_t{1} << (30 - 10 * i);
        if (bytes >= unit && bytes % unit == 0) return std::to_string(bytes / unit) + " " + kUnits[i];
    }
    return std::to_string(bytes) + " bytes";
}

}  // namespace

UntrustedFile UntrustedFile::open(const std::filesystem::path& path, const FileKind& kind) {
    UntrustedFile f;
    f.m_path = path;
    f.m_kind = kind;
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        f.m_error = "open(" + path.string() + "): " + std::strerror(errno) + " (" + kind.name + ")";
        return f;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        f.m_error = "fstat(" + path.string() + "): " + std::strerror(errno) + " (" + kind.name + ")";
        ::close(fd);
        return f;
    }
    if (!S_ISREG(st.st_mode)) {
        f.m_error = f.fail(std::string("is ") + fileTypeName(st.st_mode) + ", not a regular file");
        ::close(fd);
        return f;
    }
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (kind.max_bytes > 0 && size > kind.max_bytes) {
        f.m_error = f.fail(std::to_string(size) + " bytes, over the limit of " + bytesText(kind.max_bytes));
        ::close(fd);
        return f;
    }
    // Regular files never block; the flag only had to keep open() from waiting on a FIFO.
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags >= 0) (void)::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    f.m_fd = fd;
    f.m_size = size;
    return f;
}

std::optional<std::string> UntrustedFile::readText(const std::filesystem::path& path, const FileKind& kind,
                                                   std::string& error) {
    UntrustedFile f = open(path, kind);
    std::string text;
    if (!f.ok() || !f.readAll(text)) {
        error = f.error();
        return std::nullopt;
    }
    return text;
}

std::optional<std::vector<std::uint8_t>> UntrustedFile::readBytes(const std::filesystem::path& path,
                                                                  const FileKind& kind, std::string& error) {
    UntrustedFile f = open(path, kind);
    std::vector<std::uint8_t> bytes;
    if (!f.ok() || !f.readAll(bytes)) {
        error = f.error();
        return std::nullopt;
    }
    return bytes;
}

UntrustedFile::UntrustedFile(UntrustedFile&& other) noexcept
    : m_fd(std::exchange(other.m_fd, -1)),
      m_size(other.m_size),
      m_path(std::move(other.m_path)),
      m_kind(other.m_kind),
      m_error(std::move(other.m_error)) {}

UntrustedFile& UntrustedFile::operator=(UntrustedFile&& other) noexcept {
    if (this != &other) {
        if (m_fd >= 0) ::close(m_fd);
        m_fd = std::exchange(other.m_fd, -1);
        m_size = other.m_size;
        m_path = std::move(other.m_path);
        m_kind = other.m_kind;
        m_error = std::move(other.m_error);
    }
    return *this;
}

UntrustedFile::~UntrustedFile() {
    if (m_fd >= 0) ::close(m_fd);
}

int UntrustedFile::release() { return std::exchange(m_fd, -1); }

bool UntrustedFile::readAll(std::string& out) { return readInto(out); }

bool UntrustedFile::readAll(std::vector<std::uint8_t>& out) { return readInto(out); }

template <typename Buffer>
bool UntrustedFile::readInto(Buffer& out) {
    out.clear();
    if (m_fd < 0) {
        if (m_error.empty()) m_error = fail("not open");
        return false;
    }
    // The size seen at open, plus one byte to see the end (or growth) without a second pass; more
    // only while the cap allows. Without a cap the buffer doubles as the file turns out longer.
    const std::uint64_t cap = m_kind.max_bytes;
    std::uint64_t want = m_size + 1;
    if (cap > 0) want = std::min(want, cap + 1);
    std::size_t used = 0;
    out.resize(static_cast<std::size_t>(std::max<std::uint64_t>(want, 1)));
    for (;;) {
        if (used == out.size()) {
            if (cap > 0 && used > cap) break;
            std::uint64_t grown = std::max<std::uint64_t>(out.size() * 2, 4096);
            if (cap > 0) grown = std::min(grown, cap + 1);
            out.resize(static_cast<std::size_t>(grown));
        }
        const ssize_t n = ::read(m_fd, out.data() + used, out.size() - used);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            m_error = "read(" + m_path.string() + "): " + std::strerror(errno) + " (" + m_kind.name + ")";
            out.clear();
            return false;
        }
        if (n == 0) break;
        used += static_cast<std::size_t>(n);
    }
    if (cap > 0 && used > cap) {
        m_error = fail("grew past the limit of " + bytesText(cap) + " while being read");
        out.clear();
        return false;
    }
    out.resize(used);
    return true;
}

std::string UntrustedFile::fail(const std::string& problem) const {
    return m_path.string() + ": " + problem + " (" + m_kind.name + ")";
}

}  // namespace navmap
