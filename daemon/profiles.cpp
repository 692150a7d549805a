// SPDX-License-Identifier: Apache-2.0
#include "profiles.h"

namespace navmap::daemon {

std::vector<DisplayProfile> defaultProfiles() {
    std::vector<DisplayProfile> p = {
        {"cluster", 1280, 480, 30.0, render::ViewMode::Snail, render::Orientation::HeadingUp, "snail"},
        {"hud", 800, 240, 30.0, render::ViewMode::Snail, render::Orientation::HeadingUp, "hud"},
        {"center", 1280, 720, 30.0, render::ViewMode::Bird, render::Orientation::HeadingUp, "bird",
         render::RoadTechnique::Auto, true, false},
    };
    p[2].attribution = true;        // the map display; cluster and HUD leave it to the HMI's about screen
    p[2].speed_limit_sign.reset();  // the driver glances at the cluster and the HUD for it
    p[0].street_bar = true;         // the road driven, under the map the driver glances at
    p[2].lane_guidance = false;     // as for the sign
    return p;
}

render::MapLayers layersFor(const DisplayProfile& profile, bool labels) {
    if (isGuidanceView(profile)) return render::MapLayers::hud();  // route corridor only: no labels
    render::MapLayers layers;
    layers.labels = labels;
    layers.road_technique = profile.roads;
    layers.glow_roads = profile.glow_roads;
    layers.label_aura = profile.label_aura;
    layers.road_selection = profile.road_selection;
    return layers;
}

bool isGuidanceView(const DisplayProfile& profile) { return profile.stream_view == "hud"; }

std::optional<DisplayProfile> findProfile(const std::vector<DisplayProfile>& profiles, const std::string& name) {
    for (const auto& p : profiles) {
        if (p.name == name) return p;
    }
    return std::nullopt;
}

}  // namespace navmap::daemon
