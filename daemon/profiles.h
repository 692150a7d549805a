// SPDX-License-Identifier: Apache-2.0
#pragma once
// Display profiles (docs/architecture.md "Display profiles"): who a client is and what it is rendered with.

#include <optional>
#include <string>
#include <vector>

#include "navmap/render/camera_rig.h"
#include "navmap/render/map_frame.h"

namespace navmap::daemon {

struct DisplayProfile {
    std::string name;  ///< "cluster", "hud", "center" or a configured one
    int width = 1280;
    int height = 480;
    double fps = 30.0;
    render::ViewMode view = render::ViewMode::Snail;
    render::Orientation orientation = render::Orientation::HeadingUp;
    /// The view name frame-stream clients ask for ("snail", "bird", "hud"; docs/frame-protocol.md).
    std::string stream_view = "snail";
    /// Road draping per view (seed 3.7): geometric, shadow volumes, or chosen by DEM spacing.
    render::RoadTechnique roads = render::RoadTechnique::Auto;
    /// The occlusion aids of seed ch. 5, on in the shipped configuration: roads and the route
    /// hidden by buildings shine through (5.5.2) in every view, and buildings in front of a
    /// label fade around it (5.5.1) where labels lie in the world (snail's views); bird's-eye
    /// labels are drawn over the scene, which the seed's experts found enough there (5.4.2).
    bool glow_roads = true;
    bool label_aura = true;
    /// Minor road classes leave distant views (seed 7.3, render::MapLayers::road_selection);
    /// false: every class at every distance.
    bool road_selection = true;
    /// A camera in MapLibre GL JS's convention (`zoom`, `pitch` in the config) following the
    /// vehicle instead of the view's own distances: centred on it, bearing from `orientation`.
    /// Empty: the view's camera rig (render::CameraRig's bird's-eye or snail's view).
    std::optional<render::MapLibreFollow> camera{};
    /// "© OpenStreetMap contributors" in the bottom right corner of the frames (ODbL 4.3). On in
    /// bird's-eye views (the centre display, where the driver reads the map); off in the cluster
    /// and the HUD, glance displays where any text competes with the road ahead: the HMI shows
    /// the attribution in its own about screen there (docs/navmapd.md).
    bool attribution = false;
    /// The corner of the speed limit sign (the limit of the matched road in the driving
    /// direction, when known); none: no sign. `speed_limit_sign` in the config; by default
    /// top right in snail's and HUD views (the cluster, the HUD), none in bird's-eye views.
    std::optional<render::SignCorner> speed_limit_sign = render::SignCorner::TopRight;
    /// The current street's bar at the bottom centre (the name and ref of the road driven, once
    /// the match has held it 2 s: StreetBarHold). `street_bar` in the config; by default on in
    /// snail's views (the cluster), off in bird's-eye views and the HUD, whose guidance panel
    /// names the next street and fills its bottom.
    bool street_bar = false;
    /// The lanes before the next manoeuvre where the road has turn lanes (docs/guidance.md
    /// "Lanes"): in the HUD's guidance panel, at the bottom centre of other views.
    /// `lane_guidance` in the config; by default on except in bird's-eye views.
    bool lane_guidance = true;
};

/// The defaults: cluster 1280x480 snail's view, HUD 800x240 snail's view (route and
/// manoeuvre), center 1280x720 bird's-eye.
std::vector<DisplayProfile> defaultProfiles();

/// The map layers a profile's frames are rendered with (labels on or off for the whole daemon).
render::MapLayers layersFor(const DisplayProfile& profile, bool labels);
/// The head-up display's guidance view (`view = "hud"`): the route corridor and the next-turn
/// panel on black (render::MapLayers::hud(), docs/guidance.md), not the map.
bool isGuidanceView(const DisplayProfile& profile);

/// Looks a profile up by name among `profiles`.
std::optional<DisplayProfile> findProfile(const std::vector<DisplayProfile>& profiles, const std::string& name);

}  // namespace navmap::daemon
