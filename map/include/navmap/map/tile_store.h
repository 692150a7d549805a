// SPDX-License-Identifier: Apache-2.0
#pragma once
// Read side of a tile store file: validates the header and the index at open (the parts without
// which nothing can be read: damage there is fatal), reads and verifies single tiles on demand
// (thread-safe, pread), and loads the road graph. A damaged tile or graph is reported when it is
// read and leaves the rest usable (docs/tile-store.md "Damage").

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/store_info.h"
#include "navmap/map/tile.h"
#include "navmap/map/tile_source.h"

namespace navmap::map {

class TileStore : public TileSource {
public:
    /// Opens (a regular file only, without blocking) and validates magic, format version, header
    /// and index checksums, that every tile blob lies inside the file, and every declared size
    /// against the stored size, zlib's ratio and the format's limits (docs/tile-store.md "Sizes").
    /// Throws StoreError ("<file>: <problem>") otherwise. The road graph is not checked here
    /// (tryLoadGraph()).
    static std::shared_ptr<TileStore> open(const std::filesystem::path& path);
    ~TileStore() override;
    TileStore(const TileStore&) = delete;
    TileStore& operator=(const TileStore&) = delete;

    [[nodiscard]] const StoreInfo& info() const { return m_info; }
    [[nodiscard]] const TileScheme& scheme() const override { return m_info.scheme; }
    [[nodiscard]] Projection projection() const { return Projection(m_info.origin_lat, m_info.origin_lon); }
    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }
    [[nodiscard]] bool contains(TileId id) const override { return m_index.count(id.key()) != 0; }
    [[nodiscard]] std::uint32_t demSamples() const override { return m_info.dem_samples; }
    [[nodiscard]] std::vector<TileId> tileIds() const;
    /// Stored (compressed) size of a tile blob, 0 if absent.
    [[nodiscard]] std::uint32_t storedSize(TileId id) const;
    /// File offset of a tile blob, 0 if absent (diagnostics and tests).
    [[nodiscard]] std::uint64_t blobOffset(TileId id) const;

    using LoadResult = TileLoadResult;
    /// Reads, checks (CRC32, size), decompresses and decodes one tile, and fills the heights
    /// beyond its edges (TileDem::beyond) from the tiles of its level across them, read the same
    /// way. Never throws.
    [[nodiscard]] LoadResult load(TileId id) const override;
    /// The tile alone, as stored (TileDem::beyond empty), the caller's own to complete; null with
    /// `result.error` or `result.missing` set when it cannot be read (`result.tile` stays null).
    [[nodiscard]] std::shared_ptr<Tile> loadAlone(TileId id, LoadResult& result) const;

    struct GraphResult {
        RoadGraph graph;      ///< empty unless ok()
        std::string problem;  ///< "checksum mismatch", "the store has none", ...; empty when ok
        std::string error;    ///< "<file>: road graph: <problem>"
        [[nodiscard]] bool ok() const { return problem.empty(); }
    };
    /// Reads, checks (bounds, CRC32, declared sizes), decompresses in pieces and decodes the road
    /// graph. Never throws.
    [[nodiscard]] GraphResult tryLoadGraph() const;
    /// The same for callers that cannot work without a graph: throws StoreError on damage; a
    /// store without a graph gives an empty one.
    [[nodiscard]] RoadGraph loadGraph() const;

private:
    struct Entry {
        TileId id;
        std::uint64_t offset;
        std::uint32_t stored_size, raw_size, crc;
    };
    TileStore() = default;
    std::filesystem::path m_path;
    int m_fd = -1;
    std::uint64_t m_file_size = 0;
    StoreInfo m_info;
    std::unordered_map<std::uint64_t, Entry> m_index;
};

}  // namespace navmap::map
