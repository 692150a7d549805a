#pragma once
// Writes a tile store file: header, zlib-compressed tile blobs with CRC32, tile index, road
// graph. Written to "<path>.tmp" and renamed on finish(), so readers never see half a store.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "navmap/map/road_graph.h"
#include "navmap/map/store_info.h"
#include "navmap/map/tile.h"

namespace navmap::map {

class StoreWriter {
public:
    /// Throws StoreError when the file cannot be created. `info` supplies origin, scheme,
    /// DEM samples and bounds; counts and offsets are filled in by the writer.
    StoreWriter(std::filesystem::path path, StoreInfo info);
    ~StoreWriter();
    StoreWriter(const StoreWriter&) = delete;
    StoreWriter& operator=(const StoreWriter&) = delete;

    /// Encodes, compresses and appends one tile (each id at most once).
    void addTile(const Tile& tile);
    /// Appends an already encoded payload (used by tests to plant bad tiles).
    void addRawTile(TileId id, const std::vector<std::uint8_t>& payload);
    void setGraph(const RoadGraph& graph);
    /// Writes index and header, renames into place; returns the final file size.
    std::uint64_t finish();

    [[nodiscard]] std::uint64_t tileBytes() const { return m_tile_bytes; }

private:
    struct Entry {
        TileId id;
        std::uint64_t offset;
        std::uint32_t stored_size, raw_size, crc;
    };
    void write(const std::vector<std::uint8_t>& bytes);

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
