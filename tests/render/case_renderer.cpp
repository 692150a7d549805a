// SPDX-License-Identifier: Apache-2.0
#include "case_renderer.h"

#include <algorithm>
#include <map>
#include <memory>

#include "andorra_drive.h"
#include "navmap/render/maneuver_arrow.h"
#include "navmap/render/renderer.h"
#include "terrain_scene.h"
#include "test_paths.h"

namespace navmap::test {

namespace {

using namespace navmap::render;

std::unique_ptr<Renderer> rendererFor(const RenderCase& c) {
    RendererOptions o;
    o.width = c.width;
    o.height = c.height;
    o.msaa_samples = c.msaa_samples;
    return Renderer::create(o);
}

void addGuidance(const CaseGuidance& g, MapFrame& f) {
    if (g.arrow && f.route) f.arrows = {cutManeuverArrow(*f.route, g.junction_m, g.arrow_before_m, g.arrow_after_m)};
    if (g.junction_roads_radius_m && f.route && f.route->points.size() >= 2) {
        f.guidance_roads =
            junctionRoads(f.tiles, glm::dvec2(routeAt(*f.route, g.junction_m)), *g.junction_roads_radius_m);
    }
    f.guidance = g.overlay;
}

MapStyle styleNamed(const std::string& name) {
    if (name == "night") return MapStyle::night();
    if (name == "hud") return MapStyle::hud();
    return MapStyle::day();
}

CaseFrame renderDrive(const RenderCase& c) {
    auto renderer = rendererFor(c);
    renderer->setMapStyle(styleNamed(c.style));
    MapFrame frame = settledAndorraFrame(c.view, c.width, c.height, c.measure_m, c.speed_mps);
    frame.layers = c.layers;
    if (c.guidance) addGuidance(*c.guidance, frame);
    for (int i = 0; i < c.frames; ++i) renderer->renderMap(frame);
    return CaseFrame{renderer->readSync(), renderer->mapStats(), renderer->device().features_off};
}

const TerrainScene& terrainOf(const std::string& hgt) {
    static std::map<std::string, TerrainScene> scenes;
    auto it = scenes.find(hgt);
    if (it == scenes.end()) it = scenes.emplace(hgt, loadTerrainScene(dataDir() / hgt)).first;
    return it->second;
}

CaseFrame renderHeightfield(const RenderCase& c) {
    const TerrainScene& scene = terrainOf(c.hgt);
    auto renderer = rendererFor(c);
    renderer->setTerrain(scene.mesh);
    renderer->render(andorraOverviewCamera(scene.projection));  // the only camera case.json names
    return CaseFrame{renderer->readSync(), {}, renderer->device().features_off};
}

}  // namespace

CaseFrame renderCase(const RenderCase& c) {
    return c.scene == CaseScene::Heightfield ? renderHeightfield(c) : renderDrive(c);
}

}  // namespace navmap::test
