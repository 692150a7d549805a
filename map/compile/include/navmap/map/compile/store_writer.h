// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writes a tile store file: header, zlib-compressed tile blobs with CRC32, tile index, road
// graph. Under the store's StoreLock, into a new temporary file of a unique name in the store's
// folder (O_EXCL | O_NOFOLLOW: nothing planted there is followed or reused), fsynced and renamed
// over the store on finish(), the folder fsynced after: readers see the old store or the whole
// new one, even after a crash. The temporary file is removed on every failure.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <vector>

#include "navmap/map/road_graph.h"
#include "navmap/map/store_info.h"
#include "navmap/map/store_lock.h"
#include "navmap/map/tile.h"

namespace navmap::map {

class StoreWriter {
public:
    /// Takes the store's lock and creates the temporary file; throws StoreError when either
    /// fails (another writer, a missing folder, ...). `info` supplies origin, scheme, DEM samples
    /// and bounds; counts and offsets are filled in by the writer.
    StoreWriter(const std::filesystem::path& path, StoreInfo info);
    /// The same with a lock taken earlier (navmap-compile locks before it reads its input).
    StoreWriter(StoreLock lock, StoreInfo info);
    ~StoreWriter();
    StoreWriter(const StoreWriter&) = delete;
    StoreWriter& operator=(const StoreWriter&) = delete;

    /// Encodes, compresses and appends one tile (each id at most once).
    void addTile(const Tile& tile);
    /// Appends an already encoded payload (used by tests to plant bad tiles).
    void addRawTile(TileId id, const std::vector<std::uint8_t>& payload);
    void setGraph(const RoadGraph& graph);
    /// The same for a graph held elsewhere (on disk, by the bounded compile): `encode` hands
    /// the graph's encoding (encodeRoadGraph's bytes) to its argument in pieces, which are
    /// compressed and written as they come; the encoding is never held whole.
    using ByteSink = std::function<void(std::span<const std::uint8_t>)>;
    void writeGraph(const std::function<void(const ByteSink&)>& encode);
    /// Writes index and header, fsyncs, renames into place, fsyncs the folder; returns the
    /// final file size.
    std::uint64_t finish();

    /// The temporary file being written ("<path>.tmp-<16 hex digits>").
    [[nodiscard]] const std::filesystem::path& temporaryPath() const { return m_tmp; }

    [[nodiscard]] std::uint64_t tileBytes() const { return m_tile_bytes; }

private:
    struct Entry {
        TileId id;
        std::uint64_t offset;
        std::uint32_t stored_size, raw_size, crc;
    };
    void write(std::span<const std::uint8_t> bytes);
    void createTemporary();

    StoreLock m_lock;  // first member: released after the temporary file is gone
    std::filesystem::path m_path;
    std::filesystem::path m_tmp;
    StoreInfo m_info;
    int m_fd = -1;
    std::uint64_t m_offset = 0;
    std::uint64_t m_tile_bytes = 0;
    std::vector<Entry> m_entries;
    bool m_finished = false;
};

}  // namespace navmap::map
