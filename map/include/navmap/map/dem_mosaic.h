// SPDX-License-Identifier: Apache-2.0
#pragma once
// Several DEM tiles (e.g. adjacent SRTM .hgt files) sampled as one surface. Grids are given
// loaded (add) or as files read when first sampled and dropped again under a memory budget
// (addFile: the bounded compile, docs/tile-store.md "Bounded memory").

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "navmap/map/dem.h"

namespace navmap::map {

class DemMosaic {
public:
    /// Adds a grid; voids should be filled first (fillVoids) or they sample as NaN -> nullopt.
    void add(Dem dem);
    /// Adds an SRTM file read on first use: checked now (probeHgt: DemError naming it), loaded
    /// and void-filled (fillVoids) when a sample first falls on it, and dropped again, least
    /// recently used first, while the grids loaded from files exceed the budget (setBudget); the
    /// grid in use always stays. Samples are those of add(loadHgt() after fillVoids()).
    void addFile(const std::filesystem::path& hgt);
    /// Bytes of grids loaded from files kept at most (0, the default: no limit), but never fewer
    /// than `min_grids` grids: a tile near a DEM corner samples up to four files in turn, and
    /// dropping one of them would read it again for every sample.
    void setBudget(std::size_t bytes, std::size_t min_grids = 4) {
        m_budget = bytes;
        m_min_grids = min_grids;
    }
    /// Bilinear height at a position, or nullopt where no grid covers it.
    [[nodiscard]] std::optional<float> sample(double lat, double lon) const;
    [[nodiscard]] bool empty() const { return m_grids.empty(); }
    [[nodiscard]] std::size_t size() const { return m_grids.size(); }
    /// Files read so far (a file dropped and needed again counts again).
    [[nodiscard]] std::size_t fileLoads() const { return m_loads; }
    /// Void samples filled in the files read, each file counted once.
    [[nodiscard]] std::size_t voidsFilled() const { return m_voids_filled; }
    /// The most bytes of grids from files held at once.
    [[nodiscard]] std::size_t peakFileBytes() const { return m_peak_bytes; }

private:
    struct Grid {
        std::filesystem::path file;  // empty: given loaded (add), never dropped
        double north = 0, south = 0, west = 0, east = 0, spacing = 0;
        mutable std::optional<Dem> dem;
        mutable std::uint64_t used = 0;
        mutable bool counted = false;
    };
    const Dem& loaded(const Grid& g) const;

    std::vector<Grid> m_grids;
    std::size_t m_budget = 0;
    std::size_t m_min_grids = 4;
    // Single-threaded use by the compiler: the locality cache and the loaded files.
    mutable std::size_t m_last = 0;
    mutable std::uint64_t m_clock = 0;
    mutable std::size_t m_bytes = 0, m_peak_bytes = 0, m_loads = 0, m_voids_filled = 0;
};

}  // namespace navmap::map
