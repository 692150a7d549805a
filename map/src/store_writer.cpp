#include "navmap/map/store_writer.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <iostream>

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

}  // namespace

StoreWriter::StoreWriter(std::filesystem::path path, StoreInfo info)
    : m_path(std::move(path)), m_tmp(m_path.string() + ".tmp"), m_info(info) {
    if (m_path.has_parent_path()) {
        std::error_code ec;
        std::filesystem::create_directories(m_path.parent_path(), ec);
    }
    m_fd = ::open(m_tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (m_fd < 0) throw StoreError("open(" + m_tmp.string() + "): " + std::strerror(errno));
    write(std::vector<std::uint8_t>(detail::kHeaderSize, 0));  // patched in finish()
}

StoreWriter::~StoreWriter() {
    if (m_fd >= 0) ::close(m_fd);
    if (!m_finished) {
        std::error_code ec;
        std::filesystem::remove(m_tmp, ec);
    }
}

void StoreWriter::write(const std::vector<std::uint8_t>& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(m_fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw StoreError("write(" + m_tmp.string() + "): " + std::strerror(errno));
        }
        done += static_cast<std::size_t>(n);
    }
    m_offset += bytes.size();
}

void StoreWriter::addTile(const Tile& tile) { addRawTile(tile.id, encodeTile(tile)); }

void StoreWriter::addRawTile(TileId id, const std::vector<std::uint8_t>& payload) {
    const auto stored = compress(payload, m_tmp);
    m_entries.push_back({id, m_offset, static_cast<std::uint32_t>(stored.size()),
                         static_cast<std::uint32_t>(payload.size()), detail::crc32Of(stored)});
    m_tile_bytes += stored.size();
    write(stored);
}

void StoreWriter::setGraph(const RoadGraph& graph) {
    const auto raw = encodeRoadGraph(graph);
    const auto stored = compress(raw, m_tmp);
    m_info.graph_offset = m_offset;
    m_info.graph_stored_size = stored.size();
    m_info.graph_raw_size = raw.size();
    m_info.graph_crc = detail::crc32Of(stored);
    write(stored);
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
        throw StoreError("pwrite(" + m_tmp.string() + "): " + std::strerror(errno));
    }
    if (::close(m_fd) != 0) {
        m_fd = -1;
        throw StoreError("close(" + m_tmp.string() + "): " + std::strerror(errno));
    }
    m_fd = -1;
    std::error_code ec;
    std::filesystem::rename(m_tmp, m_path, ec);
    if (ec) throw StoreError("rename(" + m_tmp.string() + " -> " + m_path.string() + "): " + ec.message());
    m_finished = true;
    return m_offset;
}

}  // namespace navmap::map
