// SPDX-License-Identifier: Apache-2.0
#pragma once
// Typed commands of the control protocol (JSON lines over a Unix socket, docs/ipc.md), the
// limits a parser enforces, and the events a subscriber receives. Plain values, no I/O.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "navmap/common/geo_coordinate.h"
#include "navmap/common/maneuver_type.h"

namespace navmap::ipc {

/// Limits applied while parsing and serving (defaults as documented in docs/ipc.md).
struct ControlLimits {
    std::size_t max_line_bytes = std::size_t{1} << 20;  ///< a longer line disconnects the client
    std::size_t max_route_points = 20000;
    std::size_t max_maneuvers = 2000;
    std::size_t max_string_bytes = 256;  ///< ids, display names, maneuver text
};

/// The manoeuvre types and their protocol names (navmap/common/maneuver_type.h), the same enum
/// route guidance uses (map::guidance::ManeuverType).
using ManeuverType = navmap::ManeuverType;
using navmap::maneuverTypeFromName;
using navmap::maneuverTypeName;

struct Maneuver {
    std::size_t index = 0;  ///< index into the route points where the maneuver happens
    ManeuverType type = ManeuverType::Straight;
    std::string text;  ///< road name/ref or instruction, may be empty
    /// Roundabout exit counted from the entry (1 = first); only on a roundabout maneuver.
    std::optional<std::uint32_t> exit_number;
    /// Index of the route point where the maneuver is done (a roundabout's exit); absent: `index`.
    std::optional<std::size_t> end_index;
};
/// Highest roundabout exit number the protocol accepts.
inline constexpr std::uint32_t kMaxRoundaboutExit = 32;

enum class ViewMode : std::uint8_t { Bird, Snail, Auto };
enum class ViewOrientation : std::uint8_t { HeadingUp, NorthUp };
/// The map style: day or night, fixed; or Auto, the daemon choosing by the sun or the vehicle's
/// lights (docs/navmapd.md "Day and night").
enum class MapStyle : std::uint8_t { Day, Night, Auto };
/// What the terrain is coloured with: OpenStreetMap land cover or the synthetic orthoimage
/// (seed ch. 6, docs/orthoimage.md).
enum class Ground : std::uint8_t { LandCover, Orthoimage };
const char* viewModeName(ViewMode m) noexcept;                ///< "bird" | "snail" | "auto"
const char* viewOrientationName(ViewOrientation o) noexcept;  ///< "heading-up" | "north-up"
const char* mapStyleName(MapStyle s) noexcept;                ///< "day" | "night" | "auto"
const char* groundName(Ground g) noexcept;                    ///< "landcover" | "orthoimage"

/// Event kinds a client can subscribe to (bit mask values).
/// Events a subscriber hears. off_route/back_on_route: the vehicle left the active route (more
/// than the configured distance off it for the configured time) or came back to it (docs/ipc.md).
/// gpu_reset: the GL context was lost and made anew; frames wait for the map again.
enum class ControlEventKind : std::uint8_t {
    RouteProgress = 1,
    PositionLost = 2,
    PositionRegained = 4,
    OffRoute = 8,
    BackOnRoute = 16,
    GpuReset = 32,
};
inline constexpr std::uint8_t kAllControlEvents = 63;
const char* controlEventName(ControlEventKind k) noexcept;  ///< "route_progress" etc.

struct SetRouteCommand {
    std::string route_id;
    std::vector<GeoCoordinate> points;  ///< 2..max_route_points, validated ranges (navmap/common/geo_coordinate.h)
    std::vector<Maneuver> maneuvers;    ///< indices valid and non-decreasing
};
struct ClearRouteCommand {};
/// A map camera in MapLibre GL JS's convention, centred on the vehicle (docs/ipc.md set_view):
/// zoom on 512-px tiles, pitch in degrees from straight down, and an optional fixed bearing
/// (degrees clockwise from north; absent: the display's orientation decides). The protocol's
/// "pitch" and "bearing" are pitch_deg and bearing_deg here.
struct ViewCamera {
    double zoom = 0.0;                  ///< 0..24
    double pitch_deg = 0.0;             ///< 0..85
    std::optional<double> bearing_deg;  ///< -360..360
    bool operator==(const ViewCamera&) const = default;
};
/// Ranges a ViewCamera is checked against.
inline constexpr double kViewCameraMaxZoom = 24.0;
inline constexpr double kViewCameraMaxPitchDeg = 85.0;
inline constexpr double kViewCameraMaxBearingDeg = 360.0;

struct SetViewCommand {
    std::string display;           ///< "cluster", "hud", "center", ...
    std::optional<ViewMode> mode;  ///< at least one of mode/orientation/camera is given
    std::optional<ViewOrientation> orientation;
    std::optional<ViewCamera> camera;  ///< "camera": {...}
    bool clear_camera = false;         ///< "camera": null
};
/// At least one of style and ground is given; what is absent stays as it is.
struct SetStyleCommand {
    std::optional<MapStyle> style;
    std::optional<Ground> ground;
    /// The configuration's style (navmapd at start and reload), not the HMI's set_style: a fixed
    /// day style from the HMI wins over the night style in a tunnel, the configuration's does not.
    bool configured = false;
};
struct GetStatusCommand {};
struct SubscribeCommand {
    std::uint8_t events = kAllControlEvents;  ///< ControlEventKind bits
};

using ControlCommandBody = std::variant<SetRouteCommand, ClearRouteCommand, SetViewCommand, SetStyleCommand,
                                        GetStatusCommand, SubscribeCommand>;

/// One parsed request line. `request_id` is the optional "id" of a request other than set_route
/// (for set_route, "id" is the route id and required); it is echoed in the reply.
struct ControlCommand {
    std::string cmd;  ///< protocol name, e.g. "set_route"
    std::optional<std::string> request_id;
    ControlCommandBody body;
};

/// An event pushed to subscribers.
struct ControlEvent {
    ControlEventKind kind = ControlEventKind::RouteProgress;
    std::string route_id;      ///< route_progress, off_route, back_on_route
    double driven_m = 0.0;     ///< route_progress: metres driven along the route
    double remaining_m = 0.0;  ///< route_progress: metres left
    double since_s = 0.0;      ///< position_lost: seconds since the last valid position
    double offset_m = 0.0;     ///< off_route: metres between the vehicle and the route
    int resets = 0;            ///< gpu_reset: GL contexts lost and made anew since the start
};

}  // namespace navmap::ipc
