// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/dem_mosaic.h"

#include <cmath>

namespace navmap::map {

void DemMosaic::add(Dem dem) { m_dems.push_back(std::move(dem)); }

std::optional<float> DemMosaic::sample(double lat, double lon) const {
    auto covers = [&](const Dem& d) {
        const double eps = d.spacing * 1e-6;
        return lat <= d.north + eps && lat >= d.south() - eps && lon >= d.west - eps && lon <= d.east() + eps;
    };
    for (std::size_t k = 0; k < m_dems.size(); ++k) {
        const std::size_t i = (m_last + k) % m_dems.size();
        if (covers(m_dems[i])) {
            m_last = i;
            const float h = m_dems[i].sample(lat, lon);
            if (std::isnan(h)) return std::nullopt;
            return h;
        }
    }
    return std::nullopt;
}

}  // namespace navmap::map
