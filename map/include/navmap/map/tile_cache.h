// SPDX-License-Identifier: Apache-2.0
#pragma once
// Out-of-core tile cache: the render thread asks for the tiles it wants each frame and gets
// what is resident immediately; one background thread loads the rest in priority order; an
// LRU keeps resident bytes under a budget (seed 6.5: visible tiles are streamed from the
// hierarchical database into main memory).

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "navmap/map/tile.h"
#include "navmap/map/tile_source.h"

namespace navmap::map {

struct TileRequest {
    TileId id;
    float priority = 0;  ///< higher loads first
};

struct TileCacheOptions {
    std::size_t budget_bytes = std::size_t{256} << 20;  ///< resident Tile::byteSize() limit
    bool log_errors = true;                             ///< print each corrupt tile once to stderr
};

struct TileCacheMetrics {
    std::uint64_t hits = 0;    ///< requested tiles that were resident
    std::uint64_t misses = 0;  ///< requested tiles not resident and newly queued for loading
    std::uint64_t loads = 0;   ///< tiles read from the store
    std::uint64_t evictions = 0;
    std::uint64_t dropped_over_budget = 0;  ///< loaded tiles discarded: everything resident was wanted
    std::uint64_t corrupt = 0;              ///< tiles that failed checksum/decoding (skipped afterwards)
    double load_p50_ms = 0;                 ///< over the last 4096 loads
    double load_p99_ms = 0;
    std::size_t resident_bytes = 0;
    std::size_t peak_resident_bytes = 0;
    std::size_t resident_tiles = 0;
    std::size_t pending = 0;
    std::size_t budget_bytes = 0;
    std::string last_error;
};

class TileCache {
public:
    TileCache(std::shared_ptr<const TileSource> source, TileCacheOptions options = {});
    ~TileCache();
    TileCache(const TileCache&) = delete;
    TileCache& operator=(const TileCache&) = delete;

    /// Render thread: returns, for each wanted id in order, the resident tile or null, and
    /// replaces loader queue `queue` with the wanted tiles that are not resident (older requests
    /// to that queue are superseded). Several views of one cache (navmapd's displays) each use a
    /// queue of their own, so that one view's request does not drop another's; the loader
    /// serves the lowest-numbered queue with work first (the cluster before the other
    /// profiles). Never does I/O; holds a mutex only for bookkeeping.
    std::vector<std::shared_ptr<const Tile>> request(std::span<const TileRequest> wanted, int queue = 0);

    /// The resident tile or null; no bookkeeping.
    [[nodiscard]] std::shared_ptr<const Tile> find(TileId id) const;
    [[nodiscard]] TileCacheMetrics metrics() const;
    [[nodiscard]] std::vector<TileId> corruptTiles() const;
    /// Waits until the queue is empty and nothing is loading (tests, benchmarks, warm-up).
    bool waitIdle(std::chrono::milliseconds timeout) const;
    /// The source the tiles come from. Valid until replaceSource(); call both on one thread.
    [[nodiscard]] const TileSource& source() const { return *m_source; }
    /// Switches to another source with the same scheme and tile ids (the same stores in another
    /// frame: StoreSet::inFrame). Every resident tile is dropped; the ones the latest requests
    /// wanted are loaded from the new source on the calling thread before it returns, so the next
    /// frame finds them; a load in flight from the old source is discarded. Returns how many tiles
    /// were loaded.
    std::size_t replaceSource(std::shared_ptr<const TileSource> source);

private:
    struct Resident {
        std::shared_ptr<const Tile> tile;
        std::list<std::uint64_t>::iterator lru;
        std::size_t bytes = 0;
        std::uint64_t generation = 0;  ///< last request() generation that wanted it
    };
    void loaderLoop();
    // Makes a loaded tile resident (m_mutex held; the caller made room for it).
    void admit(std::uint64_t key, std::shared_ptr<const Tile> tile, std::size_t bytes);
    void touch(Resident& r);
    // The queue the loader serves next, or null when every queue is empty (m_mutex held).
    std::vector<TileRequest>* nextQueue();
    [[nodiscard]] std::size_t pendingCount() const;  // m_mutex held

    std::shared_ptr<const TileSource> m_source;
    TileCacheOptions m_options;
    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    mutable std::condition_variable m_idle;
    std::unordered_map<std::uint64_t, Resident> m_resident;
    std::list<std::uint64_t> m_lru;  ///< front = most recently used
    /// Per queue (request()): sorted, highest priority last (popped from back); lowest queue first.
    std::map<int, std::vector<TileRequest>> m_pending;
    std::unordered_set<std::uint64_t> m_bad;      ///< corrupt or absent: never retried
    std::unordered_set<std::uint64_t> m_dropped;  ///< dropped over budget until something is evicted
    std::uint64_t m_in_flight = ~std::uint64_t{0};
    std::uint64_t m_generation = 0;
    std::uint64_t m_source_epoch = 0;  ///< counts replaceSource(): loads from an older source are dropped
    std::vector<double> m_load_ms;     ///< ring of recent load times
    std::size_t m_load_next = 0;
    std::vector<TileId> m_corrupt_ids;
    TileCacheMetrics m_metrics;
    bool m_stop = false;
    std::thread m_thread;
};

}  // namespace navmap::map
