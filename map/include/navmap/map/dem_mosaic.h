// SPDX-License-Identifier: Apache-2.0
#pragma once
// Several DEM tiles (e.g. adjacent SRTM .hgt files) sampled as one surface.

#include <optional>
#include <vector>

#include "navmap/map/dem.h"

namespace navmap::map {

class DemMosaic {
public:
    /// Adds a grid; voids should be filled first (fillVoids) or they sample as NaN -> nullopt.
    void add(Dem dem);
    /// Bilinear height at a position, or nullopt where no grid covers it.
    [[nodiscard]] std::optional<float> sample(double lat, double lon) const;
    [[nodiscard]] bool empty() const { return m_dems.empty(); }
    [[nodiscard]] std::size_t size() const { return m_dems.size(); }

private:
    std::vector<Dem> m_dems;
    mutable std::size_t m_last = 0;  // locality cache (single-threaded use by the compiler)
};

}  // namespace navmap::map
