// SPDX-License-Identifier: Apache-2.0
// Labels as the driver sees them in the shipped configuration (daemon/navmapd.toml): every
// profile rendered along the Andorra drive with the layers navmapd gives it, and what is drawn
// checked frame by frame: no text over other text, none over the vehicle marker, no capitals
// under 9 px, no world-space label hidden by the scene more than 10 % (seed 5.1: every label
// readable; 5.5.1: the aura makes the hidden ones readable).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "andorra_drive.h"
#include "config.h"
#include "drawn_geometry.h"
#include "navmap/render/image.h"
#include "navmap/render/renderer.h"
#include "profiles.h"
#include "test_paths.h"

namespace {

using namespace navmap;
using render::labels::DrawnLabel;

struct Findings {
    std::size_t frames = 0, visible = 0, world = 0;
    std::size_t overlaps = 0, under_marker = 0, too_small = 0, occluded = 0, unmeasured = 0;
    std::size_t leaving_hidden = 0;  // label frames cut by terrain while fading out (not counted as occluded)
    std::string first;               // the first finding, described
};

void note(Findings& f, const std::string& what) {
    if (f.first.empty()) f.first = what;
}

// Renders `frames` frames of the drive from `start_m` with the profile as navmapd renders it and
// checks the drawn labels of each after the first `settle` frames.
Findings driveProfile(const daemon::DisplayProfile& p, bool labels, double start_m, int settle, int frames) {
    test::DriveScene& d = test::andorraDrive();
    render::RendererOptions o;
    o.width = p.width;
    o.height = p.height;
    auto r = render::Renderer::create(o);
    render::CameraRig rig;
    rig.setMode(p.view);
    rig.setOrientation(p.orientation);
    const double aspect = double(p.width) / p.height;
    const auto terrain = [&](double x, double y) { return d.view->terrainHeight(x, y); };
    const double dt = 1.0 / p.fps;
    Findings f;
    double measure = start_m;
    for (int i = 0; i < settle + frames; ++i) {
        measure += 13.0 * dt;
        const render::VehiclePose pose = test::poseAlong(d.drive, measure, 13.0, terrain);
        render::MapFrame frame;
        frame.camera = rig.update(pose, i == 0 ? 0.0 : dt, terrain);
        d.view->warmUp(frame.camera, aspect, p.height, std::chrono::seconds(10));
        d.view->select(frame, aspect, p.height);
        frame.route = &d.drive.geometry;
        frame.route_progress_m = measure;
        frame.marker = render::MarkerState{pose.position, pose.heading_deg, false};
        frame.layers = daemon::layersFor(p, labels);
        frame.layers.measure_label_occlusion = true;
        frame.frame_dt_s = dt;
        r->renderMap(frame);
        if (i < settle) continue;
        const render::MapFrameStats& s = r->mapStats();
        ++f.frames;
        std::vector<const DrawnLabel*> visible;
        for (const DrawnLabel& l : s.drawn_labels) {
            if (l.opacity >= 0.5F) visible.push_back(&l);
        }
        f.visible += visible.size();
        char buf[256];
        for (std::size_t a = 0; a < visible.size(); ++a) {
            const DrawnLabel& la = *visible[a];
            f.world += la.world_space;
            if (la.cap_height_px < 9.0F) {
                ++f.too_small;
                std::snprintf(buf, sizeof buf, "frame %d: \"%s\" has %.1f px capitals", i, la.text.c_str(),
                              la.cap_height_px);
                note(f, buf);
            }
            if (la.world_space && la.occluded_fraction < 0.0F) ++f.unmeasured;
            // A label fading out after its anchor went behind a hill is cut by the hill on its way out.
            const auto placed = std::find_if(s.placed_labels.begin(), s.placed_labels.end(),
                                             [&](const auto& q) { return q.id == la.id; });
            const bool leaving =
                placed != s.placed_labels.end() && placed->state == render::labels::LabelState::FadingOut;
            f.leaving_hidden += leaving && la.occluded_fraction > 0.10F;
            if (!leaving && la.occluded_fraction > 0.10F) {
                ++f.occluded;
                std::snprintf(buf, sizeof buf, "frame %d: \"%s\" %.0f %% hidden", i, la.text.c_str(),
                              100.0 * la.occluded_fraction);
                note(f, buf);
            }
            if (test::overlapsPolygon(la.glyph_boxes, s.drawn_marker.outline, 1.0F)) {
                ++f.under_marker;
                std::snprintf(buf, sizeof buf, "frame %d: \"%s\" over the marker", i, la.text.c_str());
                note(f, buf);
            }
            for (std::size_t b = a + 1; b < visible.size(); ++b) {
                if (test::glyphsOverlap(la.glyph_boxes, visible[b]->glyph_boxes, 1.0F)) {
                    ++f.overlaps;
                    std::snprintf(buf, sizeof buf, "frame %d: \"%s\" over \"%s\"", i, la.text.c_str(),
                                  visible[b]->text.c_str());
                    note(f, buf);
                }
            }
        }
    }
    return f;
}

class ShippedProfiles : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedProfiles, DrawnLabelsAreReadableAndClear) {
    daemon::ConfigError err;
    const auto config = daemon::loadConfig(test::sourceDir() / "daemon" / "navmapd.toml", &err);
    ASSERT_TRUE(config) << err.message;
    const auto p = daemon::findProfile(config->profiles, GetParam());
    ASSERT_TRUE(p) << GetParam() << " is not in the shipped configuration";
    EXPECT_TRUE(config->labels);
    // Through the centre of Andorra la Vella and Escaldes: the densest labels of the data.
    const Findings f = driveProfile(*p, config->labels, 1500.0, 45, 75);
    std::printf(
        "%s: %zu frames, %.1f visible labels per frame (%zu world-space), overlaps %zu, under the marker %zu, "
        "too small %zu, hidden %zu (%zu more while fading out)\n",
        GetParam().c_str(), f.frames, double(f.visible) / double(f.frames), f.world, f.overlaps, f.under_marker,
        f.too_small, f.occluded, f.leaving_hidden);
    if (daemon::isGuidanceView(*p)) {
        // The head-up display shows the guidance view: the route corridor and the next turn, no labels.
        EXPECT_EQ(f.visible, 0U) << "the HUD's guidance view draws no map labels";
    } else {
        EXPECT_GE(f.visible, f.frames * 3) << "the drive should show labels";
    }
    EXPECT_EQ(f.overlaps, 0U) << f.first;
    EXPECT_EQ(f.under_marker, 0U) << f.first;
    EXPECT_EQ(f.too_small, 0U) << f.first;
    EXPECT_EQ(f.occluded, 0U) << f.first;
    EXPECT_EQ(f.unmeasured, 0U) << "every world-space label gets its occlusion measured";
}

INSTANTIATE_TEST_SUITE_P(Navmapd, ShippedProfiles, ::testing::Values("cluster", "hud", "center"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
