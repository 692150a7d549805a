// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/projection.h"

#include <GeographicLib/Constants.hpp>

namespace navmap::map {

Projection::Projection(double origin_lat, double origin_lon)
    : m_tm(GeographicLib::Constants::WGS84_a(), GeographicLib::Constants::WGS84_f(), 1.0),
      m_origin_lat(origin_lat),
      m_origin_lon(origin_lon) {
    double x = 0.0;
    m_tm.Forward(m_origin_lon, m_origin_lat, m_origin_lon, x, m_origin_northing);
}

PlanarPoint Projection::forward(double lat, double lon) const {
    PlanarPoint p;
    m_tm.Forward(m_origin_lon, lat, lon, p.x, p.y);
    p.y -= m_origin_northing;
    return p;
}

void Projection::reverse(PlanarPoint p, double& lat, double& lon) const {
    m_tm.Reverse(m_origin_lon, p.x, p.y + m_origin_northing, lat, lon);
}

}  // namespace navmap::map
