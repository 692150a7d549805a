// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/tile_cache.h"

#include "navmap/common/percentile.h"

#include <algorithm>
#include <cmath>
#include <iostream>

namespace navmap::map {

namespace {
constexpr std::uint64_t kNone = ~std::uint64_t{0};
constexpr std::size_t kLoadWindow = 4096;
}  // namespace

TileCache::TileCache(std::shared_ptr<const TileSource> source, TileCacheOptions options)
    : m_source(std::move(source)), m_options(options) {
    m_metrics.budget_bytes = options.budget_bytes;
    m_thread = std::thread([this] { loaderLoop(); });
}

TileCache::~TileCache() {
    {
        std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    if (m_thread.joinable()) m_thread.join();
}

void TileCache::touch(Resident& r) {
    m_lru.splice(m_lru.begin(), m_lru, r.lru);
    r.generation = m_generation;
}

std::vector<TileRequest>* TileCache::nextQueue() {
    for (auto& [queue, pending] : m_pending) {
        if (!pending.empty()) return &pending;
    }
    return nullptr;
}

std::size_t TileCache::pendingCount() const {
    std::size_t n = 0;
    for (const auto& [queue, pending] : m_pending) n += pending.size();
    return n;
}

std::vector<std::shared_ptr<const Tile>> TileCache::request(std::span<const TileRequest> wanted, int queue) {
    std::vector<std::shared_ptr<const Tile>> out(wanted.size());
    {
        std::lock_guard lock(m_mutex);
        ++m_generation;
        std::vector<TileRequest> pending;
        std::unordered_set<std::uint64_t> queued_before;
        for (const auto& [q, queued] : m_pending) {
            for (const auto& p : queued) queued_before.insert(p.id.key());
        }
        for (std::size_t i = 0; i < wanted.size(); ++i) {
            const std::uint64_t key = wanted[i].id.key();
            if (auto it = m_resident.find(key); it != m_resident.end()) {
                ++m_metrics.hits;
                touch(it->second);
                out[i] = it->second.tile;
                continue;
            }
            if (m_bad.count(key) || m_dropped.count(key) || !m_source->contains(wanted[i].id)) continue;
            if (key != m_in_flight) {
                if (!queued_before.count(key)) ++m_metrics.misses;
                pending.push_back(wanted[i]);
            }
        }
        // Deduplicate (keep the highest priority) and order so the best is at the back.
        std::sort(pending.begin(), pending.end(), [](const TileRequest& a, const TileRequest& b) {
            return a.id.key() != b.id.key() ? a.id.key() < b.id.key() : a.priority > b.priority;
        });
        pending.erase(std::unique(pending.begin(), pending.end(),
                                  [](const TileRequest& a, const TileRequest& b) { return a.id.key() == b.id.key(); }),
                      pending.end());
        std::stable_sort(pending.begin(), pending.end(),
                         [](const TileRequest& a, const TileRequest& b) { return a.priority < b.priority; });
        m_pending[queue] = std::move(pending);
    }
    m_wake.notify_one();
    return out;
}

std::shared_ptr<const Tile> TileCache::find(TileId id) const {
    std::lock_guard lock(m_mutex);
    const auto it = m_resident.find(id.key());
    return it == m_resident.end() ? nullptr : it->second.tile;
}

void TileCache::loaderLoop() {
    std::unique_lock lock(m_mutex);
    for (;;) {
        m_wake.wait(lock, [&] { return m_stop || nextQueue() != nullptr; });
        if (m_stop) return;
        std::vector<TileRequest>& queue = *nextQueue();
        const TileRequest next = queue.back();
        queue.pop_back();
        const std::uint64_t key = next.id.key();
        if (m_resident.count(key)) continue;
        m_in_flight = key;
        const std::shared_ptr<const TileSource> source = m_source;
        const std::uint64_t epoch = m_source_epoch;
        lock.unlock();

        const auto start = std::chrono::steady_clock::now();
        TileLoadResult loaded = source->load(next.id);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

        lock.lock();
        m_in_flight = kNone;
        if (epoch != m_source_epoch) {  // replaceSource() came meanwhile: this tile is in the old frame
            if (!nextQueue()) m_idle.notify_all();
            continue;
        }
        ++m_metrics.loads;
        if (m_load_ms.size() < kLoadWindow)
            m_load_ms.push_back(ms);
        else
            m_load_ms[m_load_next++ % kLoadWindow] = ms;
        if (!loaded.tile) {
            m_bad.insert(key);
            if (!loaded.missing) {
                ++m_metrics.corrupt;
                m_metrics.last_error = loaded.error;
                m_corrupt_ids.push_back(next.id);
                if (m_options.log_errors) std::cerr << "navmap: " << loaded.error << " (tile skipped)\n";
            }
        } else {
            const std::size_t bytes = loaded.tile->byteSize();
            // Evict least recently used tiles that the latest request did not ask for.
            while (m_metrics.resident_bytes + bytes > m_options.budget_bytes && !m_lru.empty()) {
                const std::uint64_t victim = m_lru.back();
                auto it = m_resident.find(victim);
                if (it->second.generation == m_generation) break;  // wanted right now
                m_metrics.resident_bytes -= it->second.bytes;
                m_lru.pop_back();
                m_resident.erase(it);
                ++m_metrics.evictions;
                m_dropped.clear();
            }
            if (m_metrics.resident_bytes + bytes > m_options.budget_bytes) {
                ++m_metrics.dropped_over_budget;
                m_dropped.insert(key);
            } else {
                admit(key, std::move(loaded.tile), bytes);
            }
        }
        if (!nextQueue()) m_idle.notify_all();
    }
}

void TileCache::admit(std::uint64_t key, std::shared_ptr<const Tile> tile, std::size_t bytes) {
    m_lru.push_front(key);
    m_resident.emplace(key, Resident{std::move(tile), m_lru.begin(), bytes, m_generation});
    m_metrics.resident_bytes += bytes;
    m_metrics.peak_resident_bytes = std::max(m_metrics.peak_resident_bytes, m_metrics.resident_bytes);
}

std::size_t TileCache::replaceSource(std::shared_ptr<const TileSource> source) {
    // Tiles wanted by the latest requests (one per display and frame) are reloaded at once.
    constexpr std::uint64_t kRecentRequests = 16;
    std::vector<TileId> wanted;
    std::shared_ptr<const TileSource> current;
    {
        std::lock_guard lock(m_mutex);
        for (const auto& [key, r] : m_resident)
            if (r.generation + kRecentRequests > m_generation) wanted.push_back(r.tile->id);
        m_source = std::move(source);
        current = m_source;
        ++m_source_epoch;
        m_resident.clear();
        m_lru.clear();
        m_pending.clear();
        m_dropped.clear();
        m_metrics.resident_bytes = 0;
    }
    std::size_t loaded_count = 0;
    for (const TileId id : wanted) {
        TileLoadResult loaded = current->load(id);
        if (!loaded.tile) continue;
        std::lock_guard lock(m_mutex);
        const std::size_t bytes = loaded.tile->byteSize();
        if (m_resident.count(id.key()) || m_metrics.resident_bytes + bytes > m_options.budget_bytes) continue;
        ++m_metrics.loads;
        admit(id.key(), std::move(loaded.tile), bytes);
        ++loaded_count;
    }
    return loaded_count;
}

TileCacheMetrics TileCache::metrics() const {
    std::lock_guard lock(m_mutex);
    TileCacheMetrics m = m_metrics;
    m.resident_tiles = m_resident.size();
    m.pending = pendingCount() + (m_in_flight != kNone ? 1 : 0);
    if (!m_load_ms.empty()) {
        m.load_p50_ms = percentile(m_load_ms, 0.50);
        m.load_p99_ms = percentile(m_load_ms, 0.99);
    }
    return m;
}

std::vector<TileId> TileCache::corruptTiles() const {
    std::lock_guard lock(m_mutex);
    return m_corrupt_ids;
}

bool TileCache::waitIdle(std::chrono::milliseconds timeout) const {
    std::unique_lock lock(m_mutex);
    return m_idle.wait_for(lock, timeout, [&] { return pendingCount() == 0 && m_in_flight == kNone; });
}

}  // namespace navmap::map
