// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/spill_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <zlib.h>

namespace navmap::map {

namespace {

std::string sysError(const char* call, const std::filesystem::path& path, int err) {
    return std::string(call) + "(" + path.string() + "): " + std::strerror(err);
}

std::uint32_t crcOf(const std::uint8_t* data, std::size_t n) {
    return static_cast<std::uint32_t>(::crc32(::crc32(0L, Z_NULL, 0), data, static_cast<uInt>(n)));
}

void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint32_t getU32(const std::uint8_t* p) {
    return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

}  // namespace

SpillWriter::SpillWriter(std::filesystem::path path, std::size_t buffer_bytes)
    : m_path(std::move(path)), m_buffer_limit(buffer_bytes) {
    m_fd = ::open(m_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (m_fd < 0) throw SpillError(sysError("open", m_path, errno));
    m_buffer.reserve(m_buffer_limit);
    m_buffer.insert(m_buffer.end(), std::begin(kSpillMagic), std::end(kSpillMagic));
}

SpillWriter::~SpillWriter() {
    if (m_fd >= 0) ::close(m_fd);
}

std::uint64_t SpillWriter::append(std::span<const std::uint8_t> payload) {
    if (m_fd < 0) throw SpillError(m_path.string() + ": append after close");
    if (payload.size() > kMaxSpillRecord) {
        throw SpillError(m_path.string() + ": a record of " + std::to_string(payload.size()) + " bytes is over the " +
                         std::to_string(kMaxSpillRecord) + " byte limit");
    }
    const std::uint64_t at = m_offset + m_buffer.size();
    putU32(m_buffer, static_cast<std::uint32_t>(payload.size()));
    putU32(m_buffer, crcOf(payload.data(), payload.size()));
    m_buffer.insert(m_buffer.end(), payload.begin(), payload.end());
    ++m_records;
    if (m_buffer.size() >= m_buffer_limit) flush();
    return at;
}

void SpillWriter::flush() {
    std::size_t done = 0;
    while (done < m_buffer.size()) {
        const ssize_t n = ::write(m_fd, m_buffer.data() + done, m_buffer.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw SpillError(sysError("write", m_path, errno));
        }
        done += static_cast<std::size_t>(n);
    }
    m_offset += m_buffer.size();
    m_buffer.clear();
}

void SpillWriter::close() {
    if (m_fd < 0) return;
    flush();
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0) throw SpillError(sysError("close", m_path, errno));
}

SpillReader::SpillReader(std::filesystem::path path) : m_path(std::move(path)) {
    m_fd = ::open(m_path.c_str(), O_RDONLY | O_CLOEXEC);
    if (m_fd < 0) throw SpillError(sysError("open", m_path, errno));
    struct stat st {};
    if (::fstat(m_fd, &st) != 0) {
        const int err = errno;
        ::close(m_fd);
        throw SpillError(sysError("fstat", m_path, err));
    }
    m_size = static_cast<std::uint64_t>(st.st_size);
    char magic[sizeof(kSpillMagic)] = {};
    if (m_size < sizeof magic) {
        ::close(m_fd);
        throw SpillError(m_path.string() + ": not a spill file (" + std::to_string(m_size) + " bytes, no header)");
    }
    readExactly(0, magic, sizeof magic, "header");
    if (std::memcmp(magic, kSpillMagic, sizeof magic) != 0) {
        ::close(m_fd);
        throw SpillError(m_path.string() + ": not a spill file (no NMSPILL1 header)");
    }
}

SpillReader::~SpillReader() {
    if (m_fd >= 0) ::close(m_fd);
}

void SpillReader::readExactly(std::uint64_t offset, void* out, std::size_t n, const char* what) const {
    if (offset + n > m_size) {
        throw SpillError(m_path.string() + ": truncated: the " + what + " at byte " + std::to_string(offset) +
                         " needs " + std::to_string(n) + " bytes, the file ends at " + std::to_string(m_size));
    }
    auto* p = static_cast<char*>(out);
    std::size_t done = 0;
    while (done < n) {
        const ssize_t got = ::pread(m_fd, p + done, n - done, static_cast<off_t>(offset + done));
        if (got < 0) {
            if (errno == EINTR) continue;
            throw SpillError(sysError("pread", m_path, errno));
        }
        if (got == 0) {
            throw SpillError(m_path.string() + ": truncated: the " + what + " at byte " + std::to_string(offset) +
                             " ends early");
        }
        done += static_cast<std::size_t>(got);
    }
}

void SpillReader::record(std::uint64_t offset, std::vector<std::uint8_t>& payload, std::uint64_t& end) const {
    std::uint8_t head[8];
    readExactly(offset, head, sizeof head, "record header");
    const std::uint32_t length = getU32(head), crc = getU32(head + 4);
    if (length > kMaxSpillRecord) {
        throw SpillError(m_path.string() + ": damaged: the record at byte " + std::to_string(offset) + " claims " +
                         std::to_string(length) + " bytes");
    }
    payload.resize(length);
    readExactly(offset + sizeof head, payload.data(), length, "record");
    if (crcOf(payload.data(), payload.size()) != crc) {
        throw SpillError(m_path.string() + ": damaged: checksum mismatch in the record at byte " +
                         std::to_string(offset));
    }
    end = offset + sizeof head + length;
}

bool SpillReader::next(std::vector<std::uint8_t>& payload) {
    if (m_pos == m_size) return false;
    record(m_pos, payload, m_pos);
    return true;
}

void SpillReader::refresh() {
    struct stat st {};
    if (::fstat(m_fd, &st) != 0) throw SpillError(sysError("fstat", m_path, errno));
    m_size = static_cast<std::uint64_t>(st.st_size);
}

void SpillReader::readAt(std::uint64_t offset, std::vector<std::uint8_t>& payload) const {
    if (offset < sizeof(kSpillMagic))
        throw SpillError(m_path.string() + ": no record at byte " + std::to_string(offset));
    std::uint64_t end = 0;
    record(offset, payload, end);
}

}  // namespace navmap::map
