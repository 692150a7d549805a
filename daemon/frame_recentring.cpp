// SPDX-License-Identifier: Apache-2.0
#include "frame_recentring.h"

#include <cmath>

namespace navmap::daemon {

double FrameRecentring::scaleError(const map::Projection& frame, double x, double y) {
    double lat = 0.0;
    double lon = 0.0;
    frame.reverse({x, y}, lat, lon);
    // Both scales are World Mercator metres per ground metre: the frame's at its origin, and the
    // one at the point (the scale a frame centred there has).
    return map::Projection(lat, lon).scale() / frame.scale() - 1.0;
}

std::optional<map::Projection> FrameRecentring::due(double x, double y) const {
    if (!std::isfinite(x) || !std::isfinite(y)) return std::nullopt;
    if (std::abs(scaleError(m_frame, x, y)) <= kMaxScaleError && std::hypot(x, y) <= kMaxDistanceM) return std::nullopt;
    double lat = 0.0;
    double lon = 0.0;
    m_frame.reverse({x, y}, lat, lon);
    return map::Projection(lat, lon);
}

map::FrameTransform FrameRecentring::adopt(const map::Projection& frame) {
    const map::FrameTransform t = frame.transformFrom(m_frame);
    m_frame = frame;
    ++m_epoch;
    return t;
}

}  // namespace navmap::daemon
