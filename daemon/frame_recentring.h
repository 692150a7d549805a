// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameRecentring: the daemon's map frame, re-centred on the vehicle as it travels. A local frame
// (map::Projection) is true to scale only at its origin's latitude: north or south of it ground is
// drawn larger or smaller against heights, road widths, the camera's metres and dead reckoning
// (about tan(lat) * 0.016 % per km). The daemon starts in the first store's frame; when the scale
// error at the vehicle passes kMaxScaleError, or the vehicle is kMaxDistanceM from the origin,
// the frame moves to the vehicle (docs/navmapd.md "Map frame"). Render thread only.

#include <cstdint>
#include <optional>

#include "navmap/map/projection.h"

namespace navmap::daemon {

class FrameRecentring {
public:
    /// Above this the frame is re-centred: 0.5 % (35 km north or south at 42 N, 12 km at 70 N).
    static constexpr double kMaxScaleError = 0.005;
    /// Farther than this from the origin the frame is re-centred too, so that positions kept as
    /// float in the frame (the road graph's shapes) keep centimetres.
    static constexpr double kMaxDistanceM = 200'000.0;

    explicit FrameRecentring(map::Projection frame) : m_frame(frame) {}

    [[nodiscard]] const map::Projection& frame() const { return m_frame; }
    /// 0 for the first frame, one more per re-centring.
    [[nodiscard]] std::uint32_t epoch() const { return m_epoch; }
    /// `frame`'s metres per ground metre at its point (x, y), minus one: how much larger than true
    /// ground is drawn there (negative: smaller).
    [[nodiscard]] static double scaleError(const map::Projection& frame, double x, double y);
    /// A frame centred on (x, y) of the current frame when that point is beyond the limits, else
    /// nullopt.
    [[nodiscard]] std::optional<map::Projection> due(double x, double y) const;
    /// Makes `frame` current; returns the transform that takes the previous frame's points into it.
    map::FrameTransform adopt(const map::Projection& frame);

private:
    map::Projection m_frame;
    std::uint32_t m_epoch = 0;
};

}  // namespace navmap::daemon
