// SPDX-License-Identifier: Apache-2.0
#pragma once
// What one map frame shows: the camera, the tiles (already chosen by level of detail), the
// route, the vehicle marker, the style and which layers are on.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "navmap/map/guidance/maneuver.h"
#include "navmap/map/tile.h"
#include "navmap/render/camera.h"
#include "navmap/render/labels/drawn_label.h"
#include "navmap/render/labels/label_layout.h"
#include "navmap/render/labels/label_types.h"
#include "navmap/render/road_style.h"

namespace navmap::render {

/// How roads are draped onto the terrain (seed ch. 3, issue #8): the geometric approach (3.4,
/// roads clipped to the terrain triangles) or shadow volumes (3.5, pixel-exact on any DEM; needs
/// the terrain layer). Auto takes shadow volumes when a drawn tile's DEM spacing is finer than
/// kShadowVolumeAutoSpacingM (the shipped SRTM store, 62.5 m, stays geometric).
enum class RoadTechnique { Geometric, ShadowVolume, Auto };
/// RoadTechnique::Auto threshold, metres between DEM samples (seed 3.7: GEO is adequate on
/// medium-resolution DEMs, SV is preferable on fine-grained ones).
inline constexpr double kShadowVolumeAutoSpacingM = 20.0;

/// Layer switches (benchmarks compare terrain only, +roads, +buildings, full).
struct MapLayers {
    bool terrain = true;
    /// The ground beyond the store's data, below the horizon (docs/rendering.md "Beyond the
    /// data"); drawn with the terrain only.
    bool far_ground = true;
    bool land_cover = true;
    bool roads = true;
    bool outlines = true;
    /// Run the outline filter only near road and route footprints (screen cells marked on the CPU,
    /// road pixels left out by a stencil bit); false: over the whole frame. Same image; the
    /// full-screen pass costs about twice as much on llvmpipe.
    bool outlines_near_roads = true;
    /// Where that filter near roads learns about the road mask. Gpu: a packing pass over the
    /// cells of the road quads (outline_pack.frag), then three fetches per pixel. Cpu: the mask is
    /// read back, its edge pixels found (outlineEdges), and the filter reads one texel per pixel
    /// over the cells that hold an edge. Auto: Cpu on software rasterizers, where the read is a
    /// copy in memory and saves llvmpipe a pass; Gpu elsewhere, where a readback would stall the
    /// pipeline. Same image either way.
    enum class OutlineMask { Auto, Gpu, Cpu } outline_mask = OutlineMask::Auto;
    /// Leave out the road pieces and buildings of tile blocks outside the view, the road pieces
    /// that road_selection leaves out of it, and the route of tiles where it lies outside the
    /// view, before the vertex stage (same image; on llvmpipe every vertex is CPU time on the
    /// render thread).
    bool cull_blocks = true;
    /// Leave out the road pieces of tile blocks that the drawn terrain hides (TerrainHorizon: a
    /// conservative horizon of the terrain's lowest heights, worked out on the CPU beside the
    /// render thread). Same image; in snail's views most distant roads lie behind ridges.
    bool cull_hidden_roads = true;
    /// Draw distant road pieces simplified (TileMesh road levels, chosen per tile block so that
    /// the simplification stays within half a pixel on screen); false: the draped pieces
    /// everywhere.
    bool road_lod = true;
    /// Leave minor road classes out of distant views (seed 7.3, RoadClassStyle::select_px): they
    /// fade out where their true width would cover too few pixels. False: every class everywhere.
    bool road_selection = true;
    /// Quads of joined road pieces reach beyond the joint only as far as the bend needs
    /// (RoadInstance::cap_reach); false: every quad holds both whole caps (seed 3.4). The same
    /// road on flat ground but for pixels on a round join's rim; on slopes fewer caps stick out
    /// of the terrain where it cuts into the road's edge.
    bool trim_joint_caps = true;
    bool buildings = true;
    bool route = true;
    bool marker = true;
    /// Map labels (seed ch. 4, 5.5): screen-space in bird's-eye, world-space in snail's view.
    /// Off by default so the label-free goldens stay valid; navmapd and the label tests turn it on.
    bool labels = false;
    /// Glowing roads (seed 5.3.5, 5.5.2): road and route parts hidden by buildings shine through.
    /// Off by default so the existing goldens stay valid.
    bool glow_roads = false;
    /// Glow colour: MapStyle::glow_color, or the road's own fill colour (seed Table 5.1 variants).
    enum class GlowMode { SingleColor, RoadColor } glow_mode = GlowMode::SingleColor;
    bool glow_blur = false;  ///< separable blur of the glow at half resolution (seed 5.5.2, optional)
    /// Transparency label aura (seed 5.3.3, 5.5.1): buildings in front of a label fade out in a
    /// smooth region around it. Needs labels; off by default.
    bool label_aura = false;
    /// Measure how much of each world-space label the scene hides, as drawn (two id renders and
    /// readbacks per frame): MapFrameStats::drawn_labels[].occluded_fraction. For quality tools
    /// and tests; off in production.
    bool measure_label_occlusion = false;
    /// Road draping technique; Geometric by default (the existing goldens are geometric).
    RoadTechnique road_technique = RoadTechnique::Geometric;

    /// The head-up display's guidance style (profile "hud"): only the route, the manoeuvre arrows
    /// and MapFrame::guidance_roads, drawn bright on black (black is transparent on a HUD
    /// combiner); no terrain, land cover, map roads, buildings, labels or outlines. Pair it with
    /// MapStyle::hud(). The guidance overlay (MapFrame::guidance) is drawn in any style.
    static MapLayers hud();
};

/// The planned route as a polyline on the terrain (store-frame metres), with the distance
/// along the route at each point.
struct RouteGeometry {
    std::vector<glm::dvec3> points;
    std::vector<double> measure_m;  ///< same size as points, increasing
    /// Bumped by the owner whenever points or measures change: the renderer re-drapes the route
    /// onto its tiles when this (or the object) changes. Point z is not used for drawing.
    std::uint64_t version = 0;
    /// The parts of the route that run in a tunnel, as [from, to] distances along the route
    /// (metres, ascending, not overlapping): drawn dashed on the surface above the tunnel, since
    /// the tunnel itself is under the terrain. navmapd finds them on the road graph
    /// (docs/rendering.md "Tunnels and layers"). Part of the route's geometry: change `version`
    /// with it.
    std::vector<std::pair<double, double>> tunnels_m;
};

/// Ancestor levels a terrain tile can morph through (terrain_lod.h: a tile reaches several
/// morph ranges deep, since tiles are large against the level-of-detail distances).
inline constexpr int kMorphLevels = 4;

/// Geomorphing of one drawn terrain tile towards its coarser levels (CDLOD-style; the rule is in
/// terrain_lod.h). Filled by MapView (lastSelection().morph), parallel to MapFrame::tiles.
struct TileMorph {
    /// ancestors[j]: the tile j + 1 levels up, parent first (null: none resident, or above the root).
    std::array<std::shared_ptr<const map::Tile>, kMorphLevels> ancestors;
    /// Slot j morphs level L - j to L - j - 1 between these camera distances; end 0: no morph.
    std::array<float, kMorphLevels> start_m{}, end_m{};
    float eye_dz_m = 0.0f;  ///< vertical distance of the camera from the LOD height band
};

struct MarkerState {
    glm::dvec3 position{0.0};  ///< store-frame metres, on the terrain
    double heading_deg = 0.0;  ///< clockwise from north
    bool stale = false;        ///< position lost: drawn grey
};

/// A manoeuvre arrow on the map (drawn by the map renderer above the route, draped on the terrain
/// like the roads, and shining through buildings with MapLayers::glow_roads): a polyline along
/// the route through the junction, from the incoming road through the turn onto the outgoing
/// road, with an arrow head at its end. cutManeuverArrow() (maneuver_arrow.h) cuts it from the
/// route. Through a roundabout the polyline follows the route round to the exit, so the arrow
/// shows the exit taken.
struct ManeuverArrow {
    /// Store-frame metres in driving order (z is not used: the arrow is draped onto each drawn
    /// tile). At least two points 0.5 m apart; the head lies on the last MapStyle::arrow_head_length_m.
    std::vector<glm::dvec3> points;
    /// 1: the next manoeuvre (full colours); less: a later one, drawn fainter (its colours mixed
    /// towards the route's by 1 - emphasis); 0 or less: not drawn. Higher emphasis draws on top.
    float emphasis = 1.0f;
};

/// The manoeuvre symbol of the guidance overlay: one per manoeuvre type of the guidance
/// (map::guidance::ManeuverType, the control protocol's set_route maneuvers[].type).
using ManeuverSymbol = map::guidance::ManeuverType;

/// The lanes before a manoeuvre (docs/rendering.md "Lane guidance"): one box per lane, left to
/// right, with its painted arrows (map::lane_arrow bits, turn_lanes.h; 0: no arrows); the lanes
/// that lead to the manoeuvre's exit bright, the others dimmed.
struct LaneRow {
    std::vector<std::uint16_t> lanes;  ///< at most 16 are drawn; none: nothing drawn
    std::uint32_t recommended = 0;     ///< bit i: lane i bright
};

/// What the guidance overlay shows (screen space, over the map; laid out for the HUD's 800 x 240
/// and scaled with the target's height): the next manoeuvre as a large symbol, the distance to
/// it, the street to turn into, and what remains of the route. Texts are UTF-8, formatted by the
/// caller; an empty text is not drawn.
struct GuidanceOverlay {
    ManeuverSymbol symbol = ManeuverSymbol::Straight;
    int roundabout_exit = 0;         ///< Roundabout: the exit to take (1 = first), shown in the ring; 0: none
    std::string distance;            ///< distance to the manoeuvre, e.g. "300 m" or "now"
    std::string street;              ///< name (or ref) of the road to turn into
    std::string remaining_distance;  ///< to the destination, e.g. "12.4 km"
    std::string remaining_time;      ///< e.g. "18 min"
    /// The lanes before the manoeuvre, in the panel above the distance; none: not drawn.
    std::optional<LaneRow> lanes;
};

/// The corner of the frame a speed limit sign stands in.
enum class SignCorner : std::uint8_t { TopLeft, TopRight, BottomLeft, BottomRight };

/// A European speed limit sign (white disc, red ring, black number) drawn over the frame in
/// screen space, sized and placed like the guidance overlay (laid out for 800 x 240 and scaled
/// with the target; docs/rendering.md "Speed limit sign").
struct SpeedLimitSign {
    int kmh = 0;  ///< the number on the sign; 0 or less: no sign
    SignCorner corner = SignCorner::TopRight;
};

/// The current street's bar: a translucent dark rounded panel across the bottom centre of the
/// frame with the name and ref of the road driven in white, "name · ref", or the one there is;
/// sized to its text, names too long cut with an ellipsis (docs/rendering.md "Street bar").
/// Both empty: no bar. The caller decides when it changes (navmapd: daemon/street_bar_hold.h).
struct StreetBar {
    std::string name;  ///< e.g. "Avinguda Meritxell"
    std::string ref;   ///< e.g. "CG-2"
    bool operator==(const StreetBar&) const = default;
};

/// What the terrain is coloured with: the flat colours of the OpenStreetMap land cover over a
/// hypsometric tint, or the synthetic orthoimage (seed ch. 6; tiles with ortho layers and
/// RendererOptions::ortho_weights; a tile whose image is not ready shows its land cover). Relief
/// shading, fog and the style's brightness apply to both (docs/orthoimage.md "In the map").
enum class Ground : std::uint8_t { LandCover, Orthoimage };

struct MapStyle {
    glm::vec3 light_dir{-0.5f, 0.6f, 0.62f};
    Ground ground = Ground::LandCover;
    glm::vec3 sky_color{0.62f, 0.75f, 0.90f};
    float brightness = 1.0f;
    /// The ground beyond the store's data (docs/rendering.md "Beyond the data"): a neutral
    /// ground, times brightness and fogged like the terrain. The sea's colour is the land cover's
    /// (render/src/tile_mesh.cpp landCoverColor), also times brightness at night.
    glm::vec3 far_ground_color{0.66f, 0.68f, 0.60f};
    float fog_start_m = 8000.0f;
    float fog_end_m = 45000.0f;
    RoadStyle roads = RoadStyle::day();
    float route_width_m = 9.0f;
    glm::vec3 route_color{0.16f, 0.45f, 0.95f};
    glm::vec3 route_casing{0.05f, 0.18f, 0.50f};
    float marker_size_px = 22.0f;
    glm::vec4 marker_color{0.95f, 0.25f, 0.15f, 1.0f};
    glm::vec4 marker_stale_color{0.55f, 0.55f, 0.55f, 1.0f};
    float building_cull_ratio = 0.004f;        ///< far small buildings: footprint / distance below this are culled
    glm::vec3 glow_color{0.45f, 1.0f, 0.35f};  ///< glowing roads, single-colour mode (seed 5.5.2: light green)
    float glow_strength = 0.8f;                ///< opacity of the glow over the buildings
    float aura_margin_px = 18.0f;              ///< seed 5.5.1: the label OOBB is enlarged by this much
    float aura_min_alpha = 0.0f;               ///< building opacity at the centre of an aura
    // Manoeuvre arrows (MapFrame::arrows): a white shaft with a dark casing and a wide head.
    float arrow_width_m = 6.0f;         ///< shaft fill width
    float arrow_casing_m = 1.5f;        ///< casing per side
    float arrow_head_width_m = 17.0f;   ///< fill width of the head at its base
    float arrow_head_length_m = 13.0f;  ///< along the polyline, at most a third of the arrow's length
    /// Arrows grow (all of their shape) beyond the route's distance scaling so that the shaft is
    /// at least this wide on screen (bird's-eye views from high up).
    float arrow_min_width_px = 5.0f;
    glm::vec3 arrow_fill{1.0f, 1.0f, 1.0f};
    glm::vec3 arrow_casing{0.08f, 0.10f, 0.16f};
    // MapFrame::guidance_roads: the roads at the next junction (HUD style), no casing.
    float guidance_road_width_m = 7.0f;
    glm::vec3 guidance_road_color{0.55f, 0.58f, 0.62f};
    // The guidance overlay (MapFrame::guidance).
    glm::vec4 guidance_panel{0.06f, 0.07f, 0.10f, 0.78f};  ///< behind symbol and texts (alpha 0: none)
    glm::vec3 guidance_symbol{1.0f, 1.0f, 1.0f};           ///< the manoeuvre's path
    glm::vec3 guidance_symbol_dim{0.45f, 0.48f, 0.52f};    ///< the roads not taken, the roundabout's ring
    glm::vec3 guidance_text{1.0f, 1.0f, 1.0f};
    // The current street's bar (MapFrame::street_bar).
    glm::vec4 street_bar_panel{0.06f, 0.07f, 0.10f, 0.72f};  ///< the rounded panel, over the map
    glm::vec3 street_bar_text{1.0f, 1.0f, 1.0f};

    static MapStyle day();
    static MapStyle night();
    /// Head-up display (with MapLayers::hud()): black background, bright route, arrow and roads.
    static MapStyle hud();
};

struct MapFrame {
    Camera camera;
    std::vector<std::shared_ptr<const map::Tile>> tiles;
    /// Parallel to tiles (MapView::select fills both); empty: tiles switch level without a morph.
    std::vector<TileMorph> tile_morph;
    const RouteGeometry* route = nullptr;
    double route_progress_m = 0.0;
    std::optional<MarkerState> marker;
    /// The vehicle is in a tunnel: the map labels (of the surface above) are left out as if
    /// MapLayers::labels were off; the guidance overlay, the speed limit sign, the route and the
    /// manoeuvre arrows stay. navmapd sets it from the matched road (docs/navmapd.md "Tunnels").
    bool hide_surface_labels = false;
    MapLayers layers;
    /// Manoeuvre arrows (any order; cutManeuverArrow() cuts them from the route). Empty: none.
    std::vector<ManeuverArrow> arrows;
    /// Road polylines drawn in MapStyle::guidance_road_color under the route (store-frame metres,
    /// draped): in the HUD style the roads that meet at the next junction, which junctionRoads()
    /// (maneuver_arrow.h) cuts from the tiles. Empty: none.
    std::vector<std::vector<glm::dvec3>> guidance_roads;
    /// The guidance overlay, drawn last over the frame; none: nothing drawn.
    std::optional<GuidanceOverlay> guidance;
    /// The speed limit sign, drawn last (after the guidance overlay); none: nothing drawn.
    std::optional<SpeedLimitSign> speed_limit;
    /// The current street's bar, drawn over the map and the labels and under the vehicle marker
    /// (which stays visible where it comes low in the frame), a keep-out area of the labels;
    /// none, or both texts empty: nothing drawn.
    std::optional<StreetBar> street_bar;
    /// The lanes before the next manoeuvre on their own panel at the top centre, drawn last with
    /// the sign, labels kept out of it (the cluster; the HUD has them in GuidanceOverlay::lanes).
    /// None or no lanes: nothing drawn.
    std::optional<LaneRow> lanes;
    /// Time since the previous frame of this renderer, seconds: the label layout advances by it
    /// (fixed simulation steps, so the result does not depend on the frame rate).
    double frame_dt_s = 1.0 / 30.0;
    /// Every tile of the frame is uploaded in it, whatever RendererOptions::max_tile_uploads_per_frame
    /// says (start-up: a frame that nobody sees until it is complete gains nothing by spreading
    /// the uploads over frames).
    bool upload_all = false;
    /// Times this frame's passes into MapFrameStats (a glFinish after each), as
    /// RendererOptions::profile_passes does for every frame: a caller samples some frames.
    bool profile_passes = false;
};

/// A tile drawn partly flat because the store had no elevation data for part of it.
struct FlatTile {
    map::TileId id;
    float coverage = 0.0f;  ///< fraction of the tile that had elevation data
};

/// Milliseconds per pass of the last map frame (measured with glFinish between passes when
/// RendererOptions::profile_passes is set, else zero) and what was drawn.
/// GL work of one pass of one frame: counted on every frame, the same on every driver and
/// machine (tests assert how it grows with the scene; benchmarks print it).
struct PassWork {
    std::uint64_t draw_calls = 0;
    std::uint64_t vertices = 0;        ///< vertices the draw calls process (count x instances)
    std::uint64_t bytes_uploaded = 0;  ///< to buffers and textures (allocations without data: 0)

    PassWork& operator+=(const PassWork& o) {
        draw_calls += o.draw_calls;
        vertices += o.vertices;
        bytes_uploaded += o.bytes_uploaded;
        return *this;
    }
};

struct MapFrameStats {
    double terrain_ms = 0, roads_ms = 0, outlines_ms = 0, buildings_ms = 0, route_ms = 0, marker_ms = 0, uploads_ms = 0,
           total_ms = 0;
    double glow_ms = 0, aura_ms = 0;  ///< glowing roads and label aura passes (seed 5.5), profiled like the others
    double label_block_ms = 0;        ///< profiled: the label pass (layout, text) and the manoeuvre arrows
    /// GL work of the passes timed above (the same slots; labels_work goes with label_block_ms),
    /// and of the whole frame (frame_work: every pass, the guidance panel and the uploads).
    PassWork uploads_work, terrain_work, buildings_work, outlines_work, roads_work, sv_roads_work, route_work,
        labels_work, aura_work, glow_work, marker_work, frame_work;
    double sv_roads_ms = 0;  ///< shadow-volume road passes (seed 3.5; roads_ms stays the geometric pass)
    bool sv_roads = false;   ///< this frame's roads were drawn as shadow volumes
    std::size_t tiles_drawn = 0;
    std::size_t tiles_uploaded = 0;
    std::size_t tiles_pending = 0;    ///< tiles not drawn yet because the upload budget was spent
    std::size_t ortho_pending = 0;    ///< orthoimages started and not finished (their tiles show land cover)
    std::size_t ortho_generated = 0;  ///< orthoimages finished in this frame
    double ortho_ms = 0;              ///< render-thread CPU time on orthoimages this frame (input vectors, GL calls)
    /// Why the orthoimage ground cannot be drawn (weights missing or unusable, driver limits, a
    /// tile's broken layers), said once in the frame that met it; empty otherwise.
    std::string ortho_problem;
    std::size_t road_segments = 0;
    std::size_t road_blocks_hidden =
        0;  ///< road blocks in view left out as hidden by the terrain (MapLayers::cull_hidden_roads)
    double horizon_ms =
        0;  ///< CPU time building the terrain's horizon for that, beside the render thread, always measured
    std::size_t terrain_triangles = 0;
    std::size_t building_triangles = 0;
    std::size_t outline_pixels =
        0;                        ///< pixels the outline filter ran on (seed 3.6.3; near roads unless the whole screen)
    double outline_cells_ms = 0;  ///< CPU time marking the screen cells near roads for that filter (from the quads, or
                                  ///< from the edges of the mask read back), always measured
    bool outline_mask_on_cpu = false;  ///< the outline filter's edges were found on the CPU (MapLayers::outline_mask)
    std::size_t flat_tiles = 0;        ///< tiles seen so far with missing elevation data
    std::vector<FlatTile> new_flat_tiles;  ///< first seen in this frame: the caller warns about them
    // Labels (MapLayers::labels).
    double labels_ms = 0;              ///< CPU time of the label pass (collect, layout, text), always measured
    std::size_t label_candidates = 0;  ///< labels of the frame's tiles projected inside the view
    std::size_t labels_visible = 0;    ///< placed labels fading in or visible
    /// World-space labels left out of this frame because their text would be drawn too small to
    /// read (LabelPass: under its minimum cap height); they fade out.
    std::size_t labels_too_small = 0;
    std::size_t label_glyphs = 0;                    ///< glyph quads drawn
    float label_world_weight = 0;                    ///< 0: screen-space labels, 1: world-space, between: cross-fading
    std::vector<labels::PlacedLabel> placed_labels;  ///< layout output of this frame (quality metrics)
    labels::LayoutStats label_layout;                ///< the layout's counters (placements, removals by reason) so far
    /// Every label drawn in this frame as it appears on screen (glyph extents after projection,
    /// drawn opacity): what the label quality metrics measure.
    std::vector<labels::DrawnLabel> drawn_labels;
    /// Candidates that arrived since the previous frame, and labels of the previous frame's
    /// layout output that are no candidates any more, with the cause (what the pop causes of
    /// navmap-label-quality attribute the pops to).
    std::vector<labels::LabelInputChange> label_input_changes;
    /// Wall time of the label occlusion measurement (MapLayers::measure_label_occlusion: its id
    /// renders and readbacks, after a glFinish so the frame's own drawing is not in it), ms; 0 when
    /// off. Tools subtract it from the frame time.
    double label_occlusion_ms = 0;
    labels::DrawnMarker drawn_marker;  ///< the vehicle marker's screen outline, empty when none was drawn
};

}  // namespace navmap::render
