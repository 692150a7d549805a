// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/dem_mosaic.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <string>

#include "navmap/map/compile/spill_file.h"

namespace navmap::map {

namespace {

std::size_t gridBytes(const Dem& d) { return d.heights.size() * sizeof(float); }

}  // namespace

void DemMosaic::add(Dem dem) {
    Grid g;
    g.north = dem.north;
    g.south = dem.south();
    g.west = dem.west;
    g.east = dem.east();
    g.spacing = dem.spacing;
    g.dem = std::move(dem);
    m_grids.push_back(std::move(g));
}

void DemMosaic::addFile(const std::filesystem::path& hgt) {
    const HgtShape shape = probeHgt(hgt);
    Grid g;
    g.file = hgt;
    g.north = shape.north;
    g.south = shape.north - shape.spacing * (shape.side - 1);
    g.west = shape.west;
    g.east = shape.west + shape.spacing * (shape.side - 1);
    g.spacing = shape.spacing;
    g.side = shape.side;
    m_grids.push_back(std::move(g));
}

Dem DemMosaic::readFile(const Grid& g) const {
    Dem dem;
    if (!g.scratch.empty()) {
        // The filled copy: the same samples as loading and filling the file again.
        SpillReader in(g.scratch);
        std::vector<std::uint8_t> bytes;
        const std::size_t n = static_cast<std::size_t>(g.side) * static_cast<std::size_t>(g.side);
        if (!in.next(bytes) || bytes.size() != n * sizeof(float)) {
            throw SpillError(g.scratch.string() + ": damaged: not the " + std::to_string(n) + " samples of " +
                             g.file.filename().string());
        }
        dem.rows = dem.cols = g.side;
        dem.north = g.north;
        dem.west = g.west;
        dem.spacing = g.spacing;
        dem.void_count = g.void_count;
        dem.heights.resize(n);
        std::memcpy(dem.heights.data(), bytes.data(), bytes.size());
        ++m_scratch_reads;
        return dem;
    }
    dem = loadHgt(g.file);
    const std::size_t filled = fillVoids(dem);
    if (!g.counted) m_voids_filled += filled;
    g.counted = true;
    g.void_count = dem.void_count;
    ++m_loads;
    if (!m_scratch.empty()) {
        const std::size_t index = static_cast<std::size_t>(&g - m_grids.data());
        const std::filesystem::path copy = m_scratch / ("dem-" + std::to_string(index) + ".grid");
        SpillWriter out(copy, 0);
        out.append(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(dem.heights.data()),  // NOLINT
                                                 dem.heights.size() * sizeof(float)));
        out.close();
        g.scratch = copy;
    }
    return dem;
}

std::vector<std::filesystem::path> DemMosaic::allVoidFiles() const {
    std::vector<std::filesystem::path> files;
    for (const Grid& g : m_grids) {
        if (!g.file.empty() && g.counted && g.void_count == static_cast<std::size_t>(g.side) * g.side)
            files.push_back(g.file);
    }
    return files;
}

const Dem& DemMosaic::loaded(const Grid& g) const {
    g.used = ++m_clock;
    if (g.dem) return *g.dem;
    Dem dem = readFile(g);
    m_bytes += gridBytes(dem);
    g.dem = std::move(dem);
    m_peak_bytes = std::max(m_peak_bytes, m_bytes);
    // Over the budget: drop the least recently used files' grids, never the one in use.
    while (m_budget > 0 && m_bytes > m_budget) {
        const Grid* oldest = nullptr;
        std::size_t held = 0;
        for (const Grid& o : m_grids) held += !o.file.empty() && o.dem;
        if (held <= m_min_grids) break;
        for (const Grid& o : m_grids) {
            if (!o.file.empty() && o.dem && &o != &g && (!oldest || o.used < oldest->used)) oldest = &o;
        }
        if (!oldest) break;
        m_bytes -= gridBytes(*oldest->dem);
        oldest->dem.reset();
    }
    return *g.dem;
}

std::optional<float> DemMosaic::sample(double lat, double lon) const {
    auto covers = [&](const Grid& d) {
        const double eps = d.spacing * 1e-6;
        return lat <= d.north + eps && lat >= d.south - eps && lon >= d.west - eps && lon <= d.east + eps;
    };
    for (std::size_t k = 0; k < m_grids.size(); ++k) {
        const std::size_t i = (m_last + k) % m_grids.size();
        if (covers(m_grids[i])) {
            m_last = i;
            const float h = loaded(m_grids[i]).sample(lat, lon);
            if (std::isnan(h)) return std::nullopt;
            return h;
        }
    }
    return std::nullopt;
}

}  // namespace navmap::map
