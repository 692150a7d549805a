// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/candump_file_source.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "navmap/common/untrusted_file.h"
#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc {

namespace {

constexpr FileKind kCandumpLog{"candump log", 0};

}  // namespace

Result<std::unique_ptr<CandumpFileSource>> CandumpFileSource::open(const std::filesystem::path& path) {
    // Regular files only, opened without blocking: a FIFO named as the log is refused at once,
    // never waited on at start-up. No size cap: the log is read in chunks of kChunkBytes.
    UntrustedFile file = UntrustedFile::open(path, kCandumpLog);
    if (!file.ok()) {
        return Error{file.error()};
    }
    return std::unique_ptr<CandumpFileSource>(new CandumpFileSource(file.release(), path));
}

CandumpFileSource::CandumpFileSource(int fd, std::filesystem::path path)
    : m_fd(fd), m_path(std::move(path)), m_reader(m_path.string()), m_chunk(kChunkBytes) {}

CandumpFileSource::~CandumpFileSource() = default;

std::size_t CandumpFileSource::bufferedBytes() const {
    return m_chunk.capacity() + m_reader.bufferedBytes() + m_ready.size() * sizeof(CandumpRecord);
}

// Reads one chunk and parses it; false at the end of the file or on a failure.
bool CandumpFileSource::fill() {
    if (m_eof || !m_failure.empty()) {
        return false;
    }
    const auto sink = [this](const CandumpRecord& r) { m_ready.push_back(r); };
    ssize_t n = 0;
    do {
        n = ::read(m_fd.get(), m_chunk.data(), m_chunk.size());
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
        m_failure = net::sysError("read", m_path.string());
        return false;
    }
    if (n == 0) {
        m_reader.finishBytes(sink);
        m_eof = true;
        return !m_ready.empty();
    }
    m_bytes_read += static_cast<std::uint64_t>(n);
    if (auto st = m_reader.feedBytes(std::string_view(m_chunk.data(), static_cast<std::size_t>(n)), sink); !st) {
        m_failure = st.message();
        m_ready.clear();  // frames before binary data are not played: the file is refused
        return false;
    }
    const auto& c = m_reader.counters();
    if (c.frames == 0 && c.malformed >= kMaxLeadingMalformed) {
        m_failure = m_path.string() + ": not a candump log: the first " + std::to_string(c.malformed) +
                    " lines are malformed (first: " +
                    (m_reader.errors().empty() ? std::string("?") : m_reader.errors().front().message) + ")";
        return false;
    }
    return true;
}

bool CandumpFileSource::next(CanFrame& out) {
    while (m_ready.empty()) {
        if (!fill()) {
            return false;
        }
    }
    out = m_ready.front().frame;
    m_ready.pop_front();
    return true;
}

bool CandumpFileSource::rewind() {
    if (!m_failure.empty()) {
        return false;
    }
    if (::lseek(m_fd.get(), 0, SEEK_SET) < 0) {
        m_failure = net::sysError("lseek", m_path.string()) + " (cannot loop this file)";
        return false;
    }
    m_reader.restartInput();
    m_ready.clear();
    m_eof = false;
    m_bytes_read = 0;
    return true;
}

}  // namespace navmap::ipc
