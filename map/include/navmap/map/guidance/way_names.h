// SPDX-License-Identifier: Apache-2.0
#pragma once
// Street names of OSM ways for guidance: the road graph keeps only way ids, the tiles keep the
// names (map::Road::name / ref). WayNames collects them from the leaf tiles a route crosses.
// Immutable after construction; thread-safe to read.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>

#include "navmap/map/projection.h"
#include "navmap/map/tile_store.h"

namespace navmap::map::guidance {

class WayNames {
public:
    WayNames() = default;

    /// Names of the roads in the leaf tiles that `route` (store frame) passes through. Tiles that
    /// fail to load are skipped and counted in loadErrors() with the last error kept.
    static WayNames alongRoute(const TileStore& store, std::span<const PlanarPoint> route);

    /// Adds a way: its name, else its ref ("CG-2"); nothing when both are empty.
    void add(std::int64_t way_id, std::string_view name, std::string_view ref);

    /// The street name of a way, or "" when unknown.
    [[nodiscard]] std::string_view lookup(std::int64_t way_id) const;
    [[nodiscard]] std::size_t size() const { return m_names.size(); }
    [[nodiscard]] std::size_t loadErrors() const { return m_load_errors; }
    [[nodiscard]] const std::string& lastError() const { return m_last_error; }

private:
    std::unordered_map<std::int64_t, std::string> m_names;
    std::size_t m_load_errors = 0;
    std::string m_last_error;
};

}  // namespace navmap::map::guidance
