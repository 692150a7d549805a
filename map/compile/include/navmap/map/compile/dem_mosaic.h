// SPDX-License-Identifier: Apache-2.0
#pragma once
// Several DEM tiles (e.g. adjacent SRTM .hgt files) sampled as one surface. Grids are given
// loaded (add) or as files read when first sampled and dropped again under a memory budget
// (addFile: the bounded compile, docs/tile-store.md "Bounded memory").

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <utility>
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
    /// A folder where grids loaded from files are kept once their voids are filled (the bounded
    /// compile's scratch folder): a grid dropped and needed again is read back from its copy
    /// there, not read and filled again (filling an SRTM3 tile takes about 25 ms, reading the copy
    /// back about 2). Empty (the default): none. Copies that cannot be written or read back are
    /// SpillErrors naming the file.
    void setScratchDir(std::filesystem::path dir) { m_scratch = std::move(dir); }
    /// Bilinear height at a position, or nullopt where no grid covers it.
    [[nodiscard]] std::optional<float> sample(double lat, double lon) const;
    [[nodiscard]] bool empty() const { return m_grids.empty(); }
    [[nodiscard]] std::size_t size() const { return m_grids.size(); }
    /// Files read so far (a file dropped and needed again counts again, unless its grid came
    /// back from the scratch folder).
    [[nodiscard]] std::size_t fileLoads() const { return m_loads; }
    /// Grids read back from their copies in the scratch folder.
    [[nodiscard]] std::size_t scratchReads() const { return m_scratch_reads; }
    /// Void samples filled in the files read, each file counted once.
    [[nodiscard]] std::size_t voidsFilled() const { return m_voids_filled; }
    /// Files read so far whose every sample is a void (-32768): they give no height at all.
    [[nodiscard]] std::vector<std::filesystem::path> allVoidFiles() const;
    /// The most bytes of grids from files held at once.
    [[nodiscard]] std::size_t peakFileBytes() const { return m_peak_bytes; }

private:
    struct Grid {
        std::filesystem::path file;  // empty: given loaded (add), never dropped
        double north = 0, south = 0, west = 0, east = 0, spacing = 0;
        int side = 0;  // samples per side of a file's grid
        mutable std::optional<Dem> dem;
        mutable std::uint64_t used = 0;
        mutable bool counted = false;
        mutable std::filesystem::path scratch;  // its filled copy, once written
        mutable std::size_t void_count = 0;
    };
    const Dem& loaded(const Grid& g) const;
    [[nodiscard]] Dem readFile(const Grid& g) const;

    std::vector<Grid> m_grids;
    std::size_t m_budget = 0;
    std::size_t m_min_grids = 4;
    std::filesystem::path m_scratch;
    // Single-threaded use by the compiler: the locality cache and the loaded files.
    mutable std::size_t m_last = 0;
    mutable std::uint64_t m_clock = 0;
    mutable std::size_t m_bytes = 0, m_peak_bytes = 0, m_loads = 0, m_voids_filled = 0, m_scratch_reads = 0;
};

}  // namespace navmap::map
