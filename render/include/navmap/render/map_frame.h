#pragma once
// What one map frame shows: the camera, the tiles (already chosen by level of detail), the
// route, the vehicle marker, the style and which layers are on.

#include <memory>
#include <optional>
#include <vector>

#include "navmap/map/tile.h"
#include "navmap/render/camera.h"
#include "navmap/render/labels/label_types.h"
#include "navmap/render/road_style.h"

namespace navmap::render {

/// Layer switches (benchmarks compare terrain only, +roads, +buildings, full).
struct MapLayers {
    bool terrain = true;
    bool land_cover = true;
    bool roads = true;
    bool outlines = true;
    bool buildings = true;
    bool route = true;
    bool marker = true;
    /// Map labels (seed ch. 4, 5.5): screen-space in bird's-eye, world-space in snail's view.
    /// Off by default so the label-free goldens stay valid; navmapd and the label tests turn it on.
    bool labels = false;
};

/// The planned route as a polyline on the terrain (store-frame metres), with the distance
/// along the route at each point.
struct RouteGeometry {
    std::vector<glm::dvec3> points;
    std::vector<double> measure_m;  ///< same size as points, increasing
};

struct MarkerState {
    glm::dvec3 position{0.0};  ///< store-frame metres, on the terrain
    double heading_deg = 0.0;  ///< clockwise from north
    bool stale = false;        ///< position lost: drawn grey
};

struct MapStyle {
    glm::vec3 light_dir{-0.5f, 0.6f, 0.62f};
    glm::vec3 sky_color{0.62f, 0.75f, 0.90f};
    float brightness = 1.0f;
    float fog_start_m = 8000.0f;
    float fog_end_m = 45000.0f;
    RoadStyle roads = RoadStyle::day();
    float route_width_m = 9.0f;
    glm::vec3 route_color{0.16f, 0.45f, 0.95f};
    glm::vec3 route_casing{0.05f, 0.18f, 0.50f};
    float marker_size_px = 22.0f;
    glm::vec4 marker_color{0.95f, 0.25f, 0.15f, 1.0f};
    glm::vec4 marker_stale_color{0.55f, 0.55f, 0.55f, 1.0f};
    float building_cull_ratio = 0.004f;  ///< far small buildings: footprint / distance below this are culled

    static MapStyle day();
    static MapStyle night();
};

struct MapFrame {
    Camera camera;
    std::vector<std::shared_ptr<const map::Tile>> tiles;
    const RouteGeometry* route = nullptr;
    double route_progress_m = 0.0;
    std::optional<MarkerState> marker;
    MapLayers layers;
    /// Time since the previous frame of this renderer, seconds: the label layout advances by it
    /// (fixed simulation steps, so the result does not depend on the frame rate).
    double frame_dt_s = 1.0 / 30.0;
};

/// A tile drawn partly flat because the store had no elevation data for part of it.
struct FlatTile {
    map::TileId id;
    float coverage = 0.0f;  ///< fraction of the tile that had elevation data
};

/// Milliseconds per pass of the last map frame (measured with glFinish between passes when
/// RendererOptions::profile_passes is set, else zero) and what was drawn.
struct MapFrameStats {
    double terrain_ms = 0, roads_ms = 0, outlines_ms = 0, buildings_ms = 0, route_ms = 0, marker_ms = 0,
           uploads_ms = 0, total_ms = 0;
    std::size_t tiles_drawn = 0;
    std::size_t tiles_uploaded = 0;
    std::size_t tiles_pending = 0;  ///< tiles not drawn yet because the upload budget was spent
    std::size_t road_segments = 0;
    std::size_t terrain_triangles = 0;
    std::size_t building_triangles = 0;
    std::size_t flat_tiles = 0;  ///< tiles seen so far with missing elevation data
    std::vector<FlatTile> new_flat_tiles;  ///< first seen in this frame: the caller warns about them
    // Labels (MapLayers::labels).
    double labels_ms = 0;                  ///< CPU time of the label pass (collect, layout, text), always measured
    std::size_t label_candidates = 0;      ///< labels of the frame's tiles projected inside the view
    std::size_t labels_visible = 0;        ///< placed labels fading in or visible
    std::size_t label_glyphs = 0;          ///< glyph quads drawn
    float label_world_weight = 0;          ///< 0: screen-space labels, 1: world-space, between: cross-fading
    std::vector<labels::PlacedLabel> placed_labels;  ///< layout output of this frame (quality metrics)
};

}  // namespace navmap::render
