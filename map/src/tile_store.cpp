// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/tile_store.h"

#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "bounded_inflate.h"
#include "graph_encoder.h"
#include "navmap/common/untrusted_file.h"
#include "navmap/map/tile_codec.h"
#include "store_header.h"

namespace navmap::map {

namespace {

/// Reads exactly n bytes at offset; false on a short read or error (errno kept).
bool preadAll(int fd, std::uint8_t* dst, std::size_t n, std::uint64_t offset) {
    std::size_t done = 0;
    while (done < n) {
        const ssize_t r = ::pread(fd, dst + done, n - done, static_cast<off_t>(offset + done));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        done += static_cast<std::size_t>(r);
    }
    return true;
}

// A tile store is not read whole: the header and the index at open, tiles and the graph when
// asked for, each checked against the file's size and its format's limits before it is read.
constexpr FileKind kStoreFile{"tile store", 0};

// The magic at the start of a payload, checked on the first piece a stream inflates to.
detail::PrefixCheck magicCheck(std::uint32_t magic, const char* what, std::array<std::uint32_t, 2> older = {}) {
    return [magic, what, older](std::span<const std::uint8_t> head, std::string& problem) {
        detail::ByteReader r(head);
        const std::uint32_t found = r.u32();
        const bool older_found = found != 0 && (found == older[0] || found == older[1]);
        if ((found == magic || older_found) && !r.failed()) return true;
        problem = std::string("not ") + what + " (bad magic)";
        return false;
    };
}

}  // namespace

std::shared_ptr<TileStore> TileStore::open(const std::filesystem::path& path) {
    std::shared_ptr<TileStore> store(new TileStore());
    store->m_path = path;
    const std::string name = path.string();
    // Without blocking, regular files only: a FIFO or a device named as a store is refused here.
    UntrustedFile file = UntrustedFile::open(path, kStoreFile);
    if (!file.ok()) throw StoreError(file.error());
    store->m_file_size = file.size();
    store->m_fd = file.release();

    std::vector<std::uint8_t> header(detail::kHeaderSize);
    const std::size_t head = std::min<std::uint64_t>(store->m_file_size, detail::kHeaderSize);
    header.resize(head);
    if (!preadAll(store->m_fd, header.data(), head, 0)) throw StoreError(name + ": cannot read header");
    std::string error;
    if (!detail::decodeHeader(header, store->m_info, error)) throw StoreError(name + ": " + error);

    StoreInfo& info = store->m_info;
    const std::uint64_t index_size = std::uint64_t{info.tile_count} * detail::kIndexEntrySize;
    if (info.index_offset < detail::kHeaderSize || info.index_offset > store->m_file_size ||
        index_size > store->m_file_size - info.index_offset) {
        throw StoreError(name + ": truncated (tile index lies beyond the end of the file)");
    }
    if (info.tile_count > detail::kMaxStoreTiles) {
        throw StoreError(name + ": the header declares " + std::to_string(info.tile_count) + " tiles, more than the " +
                         std::to_string(detail::kMaxStoreTiles) + " a store may hold");
    }
    std::vector<std::uint8_t> index(index_size);
    if (!preadAll(store->m_fd, index.data(), index.size(), info.index_offset)) {
        throw StoreError(name + ": cannot read tile index");
    }
    if (detail::crc32Of(index) != info.index_crc) throw StoreError(name + ": tile index checksum mismatch");
    detail::ByteReader r(index);
    for (std::uint32_t i = 0; i < info.tile_count; ++i) {
        Entry e{};
        e.id.level = r.u8();
        e.id.x = r.u32();
        e.id.y = r.u32();
        e.offset = r.u64();
        e.stored_size = r.u32();
        e.raw_size = r.u32();
        e.crc = r.u32();
        if (!info.scheme.valid(e.id) || e.offset < detail::kHeaderSize || e.offset > info.index_offset ||
            e.stored_size > info.index_offset - e.offset) {
            throw StoreError(name + ": index entry " + std::to_string(i) + " (tile " + e.id.toString() +
                             ") is invalid");
        }
        // Sizes by plausibility, before any tile is read: more than zlib can make of the stored
        // bytes, or more than a tile may be, is a lie of the index (a damaged or hostile store),
        // refused now rather than allocated when the tile is drawn.
        if (e.raw_size > detail::maxInflatedBytes(e.stored_size) || e.raw_size > detail::kMaxTileRawBytes) {
            throw StoreError(name + ": index entry " + std::to_string(i) + " (tile " + e.id.toString() + ") declares " +
                             std::to_string(e.raw_size) + " bytes from " + std::to_string(e.stored_size) +
                             " compressed, more than " +
                             (e.raw_size > detail::kMaxTileRawBytes
                                  ? "a tile may have (" + std::to_string(detail::kMaxTileRawBytes) + ")"
                                  : std::string("zlib's 1032:1 allows")));
        }
        if (e.stored_size > detail::maxDeflatedBytes(e.raw_size)) {
            throw StoreError(name + ": index entry " + std::to_string(i) + " (tile " + e.id.toString() + ") declares " +
                             std::to_string(e.stored_size) + " compressed bytes for " + std::to_string(e.raw_size) +
                             ", more than zlib makes of them");
        }
        store->m_index.emplace(e.id.key(), e);
    }
    // The road graph is not checked here: a damaged graph leaves the map usable (docs/tile-store.md
    // "Damage"); tryLoadGraph() reports it.
    return store;
}

TileStore::~TileStore() {
    if (m_fd >= 0) ::close(m_fd);
}

std::vector<TileId> TileStore::tileIds() const {
    std::vector<TileId> ids;
    ids.reserve(m_index.size());
    for (const auto& [key, e] : m_index) ids.push_back(e.id);
    return ids;
}

std::uint32_t TileStore::storedSize(TileId id) const {
    const auto it = m_index.find(id.key());
    return it == m_index.end() ? 0 : it->second.stored_size;
}

std::uint64_t TileStore::blobOffset(TileId id) const {
    const auto it = m_index.find(id.key());
    return it == m_index.end() ? 0 : it->second.offset;
}

TileStore::LoadResult TileStore::load(TileId id) const {
    LoadResult result;
    std::shared_ptr<Tile> tile = loadAlone(id, result);
    if (!tile) return result;
    // The heights beyond each edge, from the store (never from what a cache holds): a damaged or
    // missing tile across an edge leaves that edge one-sided.
    attachDemBorders(*tile, [this](TileId across) -> std::shared_ptr<const Tile> {
        LoadResult ignored;
        return contains(across) ? loadAlone(across, ignored) : nullptr;
    });
    result.tile = std::move(tile);
    return result;
}

std::shared_ptr<Tile> TileStore::loadAlone(TileId id, LoadResult& result) const {
    const auto it = m_index.find(id.key());
    if (it == m_index.end()) {
        result.missing = true;
        return nullptr;
    }
    const Entry& e = it->second;
    auto fail = [&](const std::string& what) {
        result.error = m_path.string() + ": tile " + id.toString() + ": " + what;
        return nullptr;
    };
    std::vector<std::uint8_t> stored(e.stored_size);
    if (!preadAll(m_fd, stored.data(), stored.size(), e.offset))
        return fail(std::string("read failed: ") + std::strerror(errno));
    if (detail::crc32Of(stored) != e.crc) return fail("checksum mismatch (corrupt tile)");
    std::vector<std::uint8_t> raw;
    std::string problem;
    if (!detail::inflateBounded(stored, e.raw_size, raw, problem, 4, magicCheck(kTilePayloadMagic, "a tile payload")))
        return fail(problem);
    auto tile = std::make_shared<Tile>();
    std::string error;
    if (!decodeTile(raw, *tile, error)) return fail("malformed payload: " + error);
    if (!(tile->id == id)) return fail("payload is for tile " + tile->id.toString());
    return tile;
}

TileStore::GraphResult TileStore::tryLoadGraph() const {
    GraphResult result;
    auto fail = [&](const std::string& problem) {
        result.graph = RoadGraph{};
        result.problem = problem;
        result.error = m_path.string() + ": road graph: " + problem;
        return std::move(result);
    };
    if (m_info.graph_stored_size == 0) return fail("the store has none");
    if (m_info.graph_offset < detail::kHeaderSize || m_info.graph_offset > m_file_size ||
        m_info.graph_stored_size > m_file_size - m_info.graph_offset) {
        return fail("lies beyond the end of the file (truncated)");
    }
    // Sizes by plausibility before anything is allocated: the format's limit and zlib's ratio.
    if (m_info.graph_raw_size > detail::kMaxGraphRawBytes) {
        return fail("declares " + std::to_string(m_info.graph_raw_size) + " bytes, more than a road graph may have (" +
                    std::to_string(detail::kMaxGraphRawBytes) + ")");
    }
    if (m_info.graph_raw_size > detail::maxInflatedBytes(m_info.graph_stored_size)) {
        return fail("declares " + std::to_string(m_info.graph_raw_size) + " bytes from " +
                    std::to_string(m_info.graph_stored_size) + " compressed, more than zlib's 1032:1 allows");
    }
    if (m_info.graph_stored_size > detail::maxDeflatedBytes(m_info.graph_raw_size)) {
        return fail("declares " + std::to_string(m_info.graph_stored_size) + " compressed bytes for " +
                    std::to_string(m_info.graph_raw_size) + ", more than zlib makes of them");
    }
    std::vector<std::uint8_t> stored(m_info.graph_stored_size);
    if (!preadAll(m_fd, stored.data(), stored.size(), m_info.graph_offset)) {
        return fail(std::string("read failed: ") + std::strerror(errno));
    }
    if (detail::crc32Of(stored) != m_info.graph_crc) return fail("checksum mismatch");
    std::vector<std::uint8_t> raw;
    std::string problem;
    if (!detail::inflateBounded(
            stored, m_info.graph_raw_size, raw, problem, 4,
            magicCheck(detail::kGraphMagic, "a road graph", {detail::kGraphMagicV2, detail::kGraphMagicV1})))
        return fail(problem);
    std::string error;
    if (!decodeRoadGraph(raw, result.graph, error)) return fail(error);
    return result;
}

RoadGraph TileStore::loadGraph() const {
    GraphResult r = tryLoadGraph();
    if (!r.ok() && r.problem != "the store has none") throw StoreError(r.error);
    return std::move(r.graph);
}

}  // namespace navmap::map
