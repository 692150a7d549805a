// SPDX-License-Identifier: Apache-2.0
#pragma once
// The label pass of the map renderer (docs/architecture.md "Render passes": after the outlines, before the
// marker): collects the label features of the frame's tiles, projects them with the frame
// camera, runs the force-based layout (seed ch. 4) on the projected text boxes and draws the
// placed labels with the SDF text layer: screen-space in bird's-eye, and in snail's view
// world-space, as part of the 3D scene (seed 5.2.1: road names along the road in 3D, place names
// standing at their place, foreshortened with distance, depth-tested), with the switching rule,
// hysteresis and cross-fade of seed 5.5. Labels keep out of the vehicle marker and the route
// just ahead of the car, a street is named once per stretch, and text too small to read is not
// shown. Private to render/.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <GLES3/gl3.h>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "labels/label_space_switch.h"
#include "navmap/map/tile.h"
#include "navmap/render/labels/label_layout.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/text/text_engine.h"
#include "road_draping.h"
#include "text/text_draw.h"

namespace navmap::render::gl {

class TextLayer;

/// One tile drawn this frame: its label features with terrain heights, and its height grid.
struct TileLabels {
    const map::Tile* tile = nullptr;
    glm::dvec3 origin{0.0};             ///< store-frame metres of the tile's south-west corner
    std::span<const glm::vec3> points;  ///< labelPoints() of the tile (empty: no labels)
    HeightGrid grid;                    ///< the tile's heights (the route's keep-out area is draped on them)
    double size_m = 0.0;                ///< edge length of the tile square
};

/// Choices of the label pass that are not layout physics (LayoutParams has those).
struct LabelPassParams {
    /// Ways of one street (same name) are labelled once within this distance of each other,
    /// metres between their anchors: a street split into many ways still gets one name per
    /// stretch of the view.
    double street_repeat_m = 500.0;
    /// Labels keep out of the route for this distance ahead of the car (the driver's next
    /// manoeuvres are there), and of the vehicle marker.
    double route_keep_out_m = 150.0;
    float keep_out_margin_px = 4.0f;  ///< added around the marker and the route's width on screen
    /// World-space text is sized by perspective (seed 5.2.1), and every label drawn is readable
    /// (seed 5.1): text whose cap height on screen, where perspective makes it smallest, would be
    /// under `world_min_cap_px` is left out and fades out; text comes in only from
    /// `world_enter_cap_px` (hysteresis). Near text is capped at `world_max_cap_ratio` times its
    /// style's cap height (nearer text keeps that size).
    float world_min_cap_px = 10.0f;
    float world_enter_cap_px = 11.0f;
    float world_max_cap_ratio = 1.5f;
    /// World-space road names lie along the road; a road running too steeply across the screen
    /// or too foreshortened (seen end-on) cannot carry readable text and gets none.
    float world_max_screen_angle_deg = 60.0f;
    float world_min_foreshortening = 0.5f;  ///< projected length over its length facing the camera
    float world_lift_m = 1.0f;              ///< text stands this far above the ground it names
    /// World-space text is drawn scaled towards the eye by 1 - this in view space, as the roads
    /// are (RoadStyle::z_offset_alpha, seed 3.6.2): a road behind the text stays behind it.
    float world_depth_pull = 0.02f;
    /// World-space text is shown only where lines of sight to it pass this far above the terrain
    /// grid (twice as far to come in).
    float terrain_clearance_m = 3.0f;
};

/// A drawn label as the occlusion effects see it (seed 5.5.1): its screen OOBB and the depth of
/// the plane it lies in.
struct LabelOccluder {
    labels::OrientedBox box;  ///< the layout box, screen pixels (origin top left, y down)
    float depth_m = 0.0f;     ///< view-space depth of the label (world-space: its plane; screen-space: its anchor)
    float alpha = 0.0f;       ///< the label's fade
};

/// Three tile-local points per label of `tile` (anchor, segment start, segment end), with z
/// on the terrain surface of `grid` (the tile's DEM, HeightGrid of its mesh).
std::vector<glm::vec3> labelPoints(const map::Tile& tile, const HeightGrid& grid);

/// Stable label id over frames and tile levels: OSM id and kind (name and anchor when the
/// feature has no OSM id).
std::uint64_t labelId(const map::Label& label, const glm::dvec3& anchor_store);

/// Fonts, shaped runs and the glyph atlas with its texture: one per renderer, shared by the label
/// passes of all its targets (each target keeps its own layout state).
struct LabelText {
    /// Loads the fonts and compiles the text shaders; throws TextError / RenderError.
    LabelText();
    ~LabelText();
    LabelText(const LabelText&) = delete;
    LabelText& operator=(const LabelText&) = delete;

    text::TextEngine engine;
    std::unique_ptr<TextLayer> layer;
};

class LabelPass {
public:
    explicit LabelPass(std::shared_ptr<LabelText> text);
    ~LabelPass();
    LabelPass(const LabelPass&) = delete;
    LabelPass& operator=(const LabelPass&) = delete;

    /// Runs one frame: layout by frame.frame_dt_s, then draws into the bound framebuffer
    /// (depth buffer of the scene attached). Fills the label fields of `stats`.
    void run(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport, MapFrameStats& stats) {
        layout(frame, tiles, viewport, stats);
        draw(viewport, stats);
    }
    /// run() in two halves, so passes that need the placed labels (the label aura) fit between.
    /// Keep-out areas: `marker`, the vehicle marker's screen outline (empty: none drawn), the next
    /// route_keep_out_m of the route and the manoeuvre arrows, as wide as `style` draws them.
    void layout(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport, MapFrameStats& stats,
                std::span<const glm::vec2> marker = {}, const MapStyle& style = {});
    void draw(glm::ivec2 viewport, MapFrameStats& stats);
    /// After draw(), with the scene's depth still bound in `depth_fbo`'s depth attachment: how
    /// much of each world-space label's text the scene hides as drawn (the aura already applied),
    /// into stats.drawn_labels[].occluded_fraction. Screen-space text is drawn over the scene
    /// and gets 0. Costs two id renders and two readbacks: for quality measurements, not for
    /// every frame.
    void measureOcclusion(GLuint depth_stencil_rb, int samples, glm::ivec2 viewport, MapFrameStats& stats);
    /// The labels of the last layout() that are drawn.
    [[nodiscard]] std::span<const LabelOccluder> occluders() const { return m_occluders; }

private:
    /// Where a world-space label stands this frame (seed 5.2.1): the plane through `origin`
    /// spanned by `right` (its baseline, along the road) and `up`, turned about the baseline
    /// to face the camera; store frame.
    struct WorldPlane {
        glm::dvec3 origin{0.0};  ///< on the ground it names, lifted by world_lift_m
        glm::vec3 right{1.0f, 0.0f, 0.0f};
        glm::vec3 up{0.0f, 0.0f, 1.0f};
        glm::vec3 normal{0.0f, -1.0f, 0.0f};
        float em_m = 1.0f;  ///< em height of its text in the world
    };
    /// A label feature, kept while it is an input or still fading out.
    struct Feature {
        std::string name;
        map::LabelKind kind = map::LabelKind::Place;
        std::uint8_t subclass = 0;
        glm::dvec3 anchor{0.0};     ///< store frame, on the terrain
        std::uint64_t frame = 0;    ///< last frame it was a candidate
        bool world = false;         ///< `plane` holds this frame's world-space placement
        bool shown_world = false;   ///< in last frame's output, in world space
        bool shown_screen = false;  ///< in last frame's output, in screen space within a world layout
        bool too_small = false;     ///< left out last time as too small to read in the world (fading out)
        /// In a drawn tile and the view but left out of the input in frame `out_frame`, and why.
        std::uint64_t out_frame = 0;
        labels::InputCause out_cause = labels::InputCause::Tiles;
        WorldPlane plane;
    };
    /// The text of a label at scale 1: measured size, cap height, and the margin its outline and
    /// halo add around the text box (px at its size).
    struct TextSize {
        glm::vec2 size{0.0f};
        float cap_height = 0.0f;
        float margin = 0.0f;
        float size_px = 0.0f;
        float world_reach = 1.0f;  ///< LabelTextStyle::world_reach
    };
    void collect(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport, bool world);
    /// How a label of a world-space layout is shown.
    enum class WorldFit {
        World,     ///< in its plane in the world
        Screen,    ///< cannot lie along its road (steep on screen, seen end-on): in screen space
        Hidden,    ///< behind the terrain: not at all
        TooSmall,  ///< its text would be drawn under world_min_cap_px: not at all (it fades out)
    };
    /// The candidate of a label drawn in the world: plane, projected box, legibility
    /// (label_pass_world.cpp, in the steps below).
    WorldFit worldCandidate(const MapFrame& frame, std::span<const TileLabels> tiles, const glm::mat4& view_projection,
                            glm::vec2 viewport, const glm::dvec3& anchor, const glm::dvec3& seg_a,
                            const glm::dvec3& seg_b, const TextSize& t, Feature& f, labels::LabelCandidate& c) const;
    struct WorldShape;
    /// The plane facing the camera: along the road or across the view; false where none can be read.
    static bool facePlane(WorldShape& w, const glm::dvec3& seg_a, const glm::dvec3& seg_b);
    /// The text's em height in the world and its smallest cap height on screen.
    bool sizeInWorld(const MapFrame& frame, const TextSize& t, WorldShape& w) const;
    /// Smallest cap height on screen of the text at em height `em` (metres); false where it is
    /// not in front of the camera.
    static bool measureCap(const TextSize& t, const WorldShape& w, float em, float& cap);
    /// The text box's corners on screen; false where a road name is too steep or foreshortened.
    bool boxOnScreen(const TextSize& t, const Feature& f, WorldShape& w) const;
    /// Whether lines of sight to points over the text pass below the terrain.
    bool hiddenByTerrain(std::span<const TileLabels> tiles, const Feature& f, const WorldShape& w) const;
    /// Whether the terrain hides an eye-relative point: lines of sight over the drawn tiles.
    /// `clearance_m`: how far above the grid the line must pass (negative: how far below it may).
    bool behindTerrain(std::span<const TileLabels> tiles, const glm::vec3& target, float clearance_m) const;
    /// Height of the finest drawn tile at a store-frame point; NaN where no tile is drawn.
    static double groundHeight(std::span<const TileLabels> tiles, double x, double y);
    /// Same-named road candidates within street_repeat_m of one already kept are dropped;
    /// labels on screen now are kept first, so the chosen way does not change.
    void dropRepeatedStreets();
    void keepOut(const MapFrame& frame, std::span<const TileLabels> tiles, glm::vec2 viewport,
                 std::span<const glm::vec2> marker, const MapStyle& style);
    const TextSize& textSize(std::uint64_t id, const map::Label& label);
    /// The input's changes since the previous frame with their causes (MapFrameStats::label_input_changes).
    void inputChanges(const MapFrame& frame, glm::vec2 viewport, MapFrameStats& stats);

    /// What layout() draws the placed labels with this frame.
    struct FrameDraw {
        const MapFrame& frame;
        glm::vec2 viewport{0.0f};
        float world = 0.0f;      ///< LabelSpaceSwitch::worldWeight()
        float spread_em = 0.0f;  ///< the glyph atlas's SDF spread, em
        float focal_px = 0.0f;
        glm::mat4 inverse_view{1.0f};
    };
    /// The frame's camera: projection, eye, view (eye-relative).
    void beginFrame(const MapFrame& frame, glm::ivec2 viewport);
    /// The text of the layout's output for draw(), its occluders and drawn labels; returns how
    /// many labels are fading in or visible.
    std::size_t prepareDraws(const MapFrame& frame, glm::vec2 viewport, float world, MapFrameStats& stats);
    void prepareLabel(const FrameDraw& d, const labels::PlacedLabel& p, const Feature& f, MapFrameStats& stats);
    /// A label's text in its world plane (seed 5.2.1), where the layout box's center is seen;
    /// false where that is not in front of the camera. `occluder_depth`: the plane's depth there.
    bool drawInWorld(const FrameDraw& d, const labels::PlacedLabel& p, const WorldPlane& pl, const text::LaidOutText& t,
                     const text::TextStyle& style, bool screen_drawn, labels::DrawnLabel& drawn, float& occluder_depth);
    /// The drawn glyph boxes and cap height on screen of world-space text centered at `center`.
    void worldGlyphBoxes(const FrameDraw& d, const glm::vec3& center, float depth, const WorldPlane& pl,
                         const text::LaidOutText& t, const text::TextStyle& style, labels::DrawnLabel& drawn) const;
    /// Forgets features neither in this frame's input nor in the output any more.
    void forgetFeatures();

    std::vector<std::size_t> m_tile_order;  ///< collect(): tiles finest first
    std::shared_ptr<LabelText> m_shared;
    text::TextEngine& m_engine;
    TextLayer& m_text;
    LabelPassParams m_params;
    labels::LabelLayout m_layout;
    labels::LabelSpaceSwitch m_switch;
    std::vector<labels::LabelCandidate> m_candidates;
    std::size_t m_too_small = 0;  ///< world-space labels of this frame left out as too small to read
    std::vector<labels::OrientedBox> m_keep_out;
    std::vector<std::uint64_t> m_shown;                        ///< ids in the layout output of the last frame, sorted
    std::vector<std::uint64_t> m_input_ids, m_prev_input_ids;  ///< candidate ids of this and the last frame, sorted
    glm::mat4 m_prev_view_projection{1.0f};                    ///< of the last frame, eye-relative
    glm::dvec3 m_prev_eye{0.0};
    glm::vec2 m_prev_viewport{0.0f};
    float m_prev_near = 0.0f;
    glm::mat4 m_view{1.0f};  ///< camera at the origin (eye-relative store frame)
    glm::mat4 m_view_projection{1.0f};
    glm::dvec3 m_eye{0.0};
    std::unordered_map<std::uint64_t, Feature> m_features;  ///< by label id
    std::vector<text::LaidOutText> m_texts;
    std::vector<text::TextDraw> m_screen;
    std::vector<text::WorldTextDraw> m_world;
    std::vector<std::size_t> m_world_drawn;  ///< index into the frame's drawn_labels, per m_world entry
    std::vector<LabelOccluder> m_occluders;
    std::uint64_t m_frame = 0;
    std::unordered_map<std::uint64_t, TextSize> m_sizes;  ///< text extent at scale 1 by id
    glm::mat4 m_projection{1.0f};
};

}  // namespace navmap::render::gl
