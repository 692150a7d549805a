// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/store_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>

#include "graph_encoder.h"
#include "navmap/common/check.h"
#include "navmap/map/tile_codec.h"
#include "store_header.h"

namespace navmap::map {

using detail::ByteWriter;

namespace {

std::vector<std::uint8_t> compress(const std::vector<std::uint8_t>& raw, const std::filesystem::path& path) {
    uLongf len = compressBound(static_cast<uLong>(raw.size()));
    std::vector<std::uint8_t> out(len);
    if (compress2(out.data(), &len, raw.data(), static_cast<uLong>(raw.size()), 6) != Z_OK) {
        throw StoreError(path.string() + ": zlib compression failed");
    }
    out.resize(len);
    return out;
}

std::string sysError(const char* call, const std::filesystem::path& object) {
    return std::string(call) + "(" + object.string() + "): " + std::strerror(errno);
}

constexpr const char* kTmpInfix = ".tmp-";
constexpr std::size_t kTmpHexDigits = 16;

/// Whether `name` is "<store name>.tmp-<16 hex digits>", a temporary file of this writer.
bool isTemporaryOf(const std::string& name, const std::string& store_name) {
    const std::string prefix = store_name + kTmpInfix;
    if (name.size() != prefix.size() + kTmpHexDigits || name.compare(0, prefix.size(), prefix) != 0) return false;
    for (std::size_t i = prefix.size(); i < name.size(); ++i) {
        if (!std::isxdigit(static_cast<unsigned char>(name[i]))) return false;
    }
    return true;
}

}  // namespace

StoreWriter::StoreWriter(const std::filesystem::path& path, StoreInfo info) : StoreWriter(StoreLock(path), info) {}

StoreWriter::StoreWriter(StoreLock lock, StoreInfo info)
    : m_lock(std::move(lock)), m_path(m_lock.store()), m_info(info) {
    createTemporary();
    try {
        write(std::vector<std::uint8_t>(detail::kHeaderSize, 0));  // patched in finish()
    } catch (...) {
        ::close(m_fd);
        m_fd = -1;
        ::unlink(m_tmp.c_str());
        throw;
    }
}

void StoreWriter::createTemporary() {
    const std::filesystem::path dir = m_path.has_parent_path() ? m_path.parent_path() : std::filesystem::path(".");
    const std::string store_name = m_path.filename().string();
    // Temporary files of writers that were killed (the lock is ours, so none is being written):
    // only regular files of ours, and unlink() never follows a link.
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        struct stat st {};
        if (isTemporaryOf(entry.path().filename().string(), store_name) && ::lstat(entry.path().c_str(), &st) == 0 &&
            S_ISREG(st.st_mode) && st.st_uid == ::geteuid()) {
            ::unlink(entry.path().c_str());
        }
    }
    // A fresh name no one can guess, created here or not at all (O_EXCL, O_NOFOLLOW). mkostemp()
    // would do the same but creates mode 0600 whatever the umask; a store is read by the daemon's
    // user, so it gets 0644 less the umask as any new file.
    std::random_device random;
    for (int attempt = 0; attempt < 16; ++attempt) {
        const std::uint64_t r = (std::uint64_t{random()} << 32) ^ random();
        char hex[kTmpHexDigits + 1];
        std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(r));
        m_tmp = m_path.string() + kTmpInfix + hex;
        m_fd = ::open(m_tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (m_fd >= 0) return;
        if (errno != EEXIST) throw StoreError(sysError("open", m_tmp));
    }
    throw StoreError(sysError("open", m_tmp) + " (16 fresh names taken)");
}

StoreWriter::~StoreWriter() {
    if (m_fd >= 0) ::close(m_fd);
    if (!m_finished && !m_tmp.empty()) ::unlink(m_tmp.c_str());
}

void StoreWriter::write(std::span<const std::uint8_t> bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(m_fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw StoreError(sysError("write", m_tmp));
        }
        done += static_cast<std::size_t>(n);
    }
    m_offset += bytes.size();
}

void StoreWriter::addTile(const Tile& tile) { addRawTile(tile.id, encodeTile(tile)); }

void StoreWriter::addRawTile(TileId id, const std::vector<std::uint8_t>& payload) {
    NAVMAP_CHECK(id.level <= 28 && (id.x >> id.level) == 0 && (id.y >> id.level) == 0, "tile x/y outside [0, 2^level)");
    const auto stored = compress(payload, m_tmp);
    m_entries.push_back({id, m_offset, static_cast<std::uint32_t>(stored.size()),
                         static_cast<std::uint32_t>(payload.size()), detail::crc32Of(stored)});
    m_tile_bytes += stored.size();
    write(stored);
}

void StoreWriter::setGraph(const RoadGraph& graph) {
    writeGraph([&](const ByteSink& sink) { detail::encodeRoadGraph(graph, sink); });
}

void StoreWriter::writeGraph(const std::function<void(const ByteSink&)>& encode) {
    // zlib's stream interface with compress2()'s settings (level 6, zlib wrapper): the same
    // bytes as compressing the whole encoding at once, whatever the pieces.
    z_stream z{};
    if (deflateInit(&z, 6) != Z_OK) throw StoreError(m_tmp.string() + ": zlib compression failed");
    const std::uint64_t offset = m_offset;
    std::uint64_t raw_size = 0;
    uLong crc = ::crc32(0L, Z_NULL, 0);
    std::vector<std::uint8_t> out(std::size_t{1} << 18);
    auto pump = [&](const std::uint8_t* data, std::size_t n, int flush) {
        z.next_in = const_cast<Bytef*>(data);  // zlib's API is not const-correct; it only reads
        z.avail_in = static_cast<uInt>(n);
        for (;;) {
            z.next_out = out.data();
            z.avail_out = static_cast<uInt>(out.size());
            const int rc = deflate(&z, flush);
            if (rc == Z_STREAM_ERROR) throw StoreError(m_tmp.string() + ": zlib compression failed");
            const std::size_t produced = out.size() - z.avail_out;
            if (produced > 0) {
                crc = ::crc32(crc, out.data(), static_cast<uInt>(produced));
                write(std::span<const std::uint8_t>(out.data(), produced));
            }
            if (flush == Z_FINISH ? rc == Z_STREAM_END : (z.avail_in == 0 && z.avail_out != 0)) break;
        }
    };
    try {
        encode([&](std::span<const std::uint8_t> piece) {
            raw_size += piece.size();
            // Pieces over zlib's uInt range go in parts.
            for (std::size_t pos = 0; pos < piece.size();) {
                const std::size_t n = std::min<std::size_t>(piece.size() - pos, std::size_t{1} << 30);
                pump(piece.data() + pos, n, Z_NO_FLUSH);
                pos += n;
            }
        });
        pump(nullptr, 0, Z_FINISH);
    } catch (...) {
        deflateEnd(&z);
        throw;
    }
    deflateEnd(&z);
    m_info.graph_offset = offset;
    m_info.graph_stored_size = m_offset - offset;
    m_info.graph_raw_size = raw_size;
    m_info.graph_crc = static_cast<std::uint32_t>(crc);
}

std::uint64_t StoreWriter::finish() {
    ByteWriter index;
    for (const auto& e : m_entries) {
        index.u8(e.id.level);
        index.u32(e.id.x);
        index.u32(e.id.y);
        index.u64(e.offset);
        index.u32(e.stored_size);
        index.u32(e.raw_size);
        index.u32(e.crc);
    }
    m_info.tile_count = static_cast<std::uint32_t>(m_entries.size());
    m_info.index_offset = m_offset;
    m_info.index_crc = detail::crc32Of(index.bytes());
    write(index.bytes());
    const auto header = detail::encodeHeader(m_info);
    if (::pwrite(m_fd, header.data(), header.size(), 0) != static_cast<ssize_t>(header.size())) {
        throw StoreError(sysError("pwrite", m_tmp));
    }
    // The data reaches the disk before the name does: a crash leaves the old store or the new one.
    if (::fsync(m_fd) != 0) throw StoreError(sysError("fsync", m_tmp));
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0) throw StoreError(sysError("close", m_tmp));
    if (::rename(m_tmp.c_str(), m_path.c_str()) != 0) {
        throw StoreError("rename(" + m_tmp.string() + " -> " + m_path.string() + "): " + std::strerror(errno));
    }
    m_finished = true;
    const std::filesystem::path dir = m_path.has_parent_path() ? m_path.parent_path() : std::filesystem::path(".");
    const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir_fd < 0) throw StoreError(sysError("open", dir) + " (to sync the rename of " + m_path.string() + ")");
    const bool synced = ::fsync(dir_fd) == 0;
    const std::string err = synced ? std::string() : sysError("fsync", dir);
    ::close(dir_fd);
    if (!synced) throw StoreError(err + " (after renaming " + m_path.string() + " into place)");
    return m_offset;
}

}  // namespace navmap::map
