// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/projection.h"

#include <cmath>

namespace navmap::map {
namespace {

/// Wraps a World Mercator x difference into [-pi a, pi a): the shorter way round the world.
double wrapX(double dx) {
    const double half = worldHalfSize();
    return dx - 2.0 * half * std::floor((dx + half) / (2.0 * half));
}

}  // namespace

Projection::Projection(double origin_lat, double origin_lon)
    : m_origin_lat(origin_lat),
      m_origin_lon(origin_lon),
      m_scale(worldMercatorScale(origin_lat)),
      m_origin(toWorldMercator(origin_lat, origin_lon)) {}

PlanarPoint Projection::fromMercator(MercatorPoint m) const {
    return {wrapX(m.x - m_origin.x) / m_scale, (m.y - m_origin.y) / m_scale};
}

MercatorPoint Projection::toMercator(PlanarPoint p) const {
    return {m_origin.x + p.x * m_scale, m_origin.y + p.y * m_scale};
}

PlanarPoint Projection::forward(double lat, double lon) const { return fromMercator(toWorldMercator(lat, lon)); }

void Projection::reverse(PlanarPoint p, double& lat, double& lon) const { fromWorldMercator(toMercator(p), lat, lon); }

FrameTransform Projection::transformFrom(const Projection& from) const {
    if (from.m_origin_lat == m_origin_lat && from.m_origin_lon == m_origin_lon) return {};
    const PlanarPoint o = fromMercator(from.m_origin);
    return {from.m_scale / m_scale, o.x, o.y};
}

}  // namespace navmap::map
