#pragma once
// The label pass of the map renderer (DESIGN.md pass order: after the outlines, before the
// marker): collects the label features of the frame's tiles, projects them with the frame
// camera, runs the force-based layout (seed ch. 4) and draws the placed labels with the SDF
// text layer, screen-space in bird's-eye and world-space (depth-tested) in snail's view, with
// the switching rule, hysteresis and cross-fade of seed 5.5. Private to render/.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "navmap/map/tile.h"
#include "navmap/render/labels/label_layout.h"
#include "navmap/render/labels/label_space_switch.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/road_draping.h"
#include "navmap/render/text/text_draw.h"
#include "navmap/render/text/text_engine.h"

namespace navmap::render::gl {

class TextLayer;

/// Label features of one tile drawn this frame, with terrain heights.
struct TileLabels {
    const map::Tile* tile = nullptr;
    glm::dvec3 origin{0.0};              ///< store-frame metres of the tile's south-west corner
    std::span<const glm::vec3> points;   ///< labelPoints() of the tile
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
    void layout(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport, MapFrameStats& stats);
    void draw(glm::ivec2 viewport, MapFrameStats& stats);
    /// The labels of the last layout() that are drawn.
    [[nodiscard]] std::span<const LabelOccluder> occluders() const { return m_occluders; }

private:
    /// A label feature, kept while it is an input or still fading out.
    struct Feature {
        std::string name;
        map::LabelKind kind = map::LabelKind::Place;
        std::uint8_t subclass = 0;
        glm::dvec3 anchor{0.0};   ///< store frame, on the terrain
        std::uint64_t frame = 0;  ///< last frame it was a candidate
    };
    void collect(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport);
    glm::vec2 labelSize(std::uint64_t id, const map::Label& label);

    std::shared_ptr<LabelText> m_shared;
    text::TextEngine& m_engine;
    TextLayer& m_text;
    labels::LabelLayout m_layout;
    labels::LabelSpaceSwitch m_switch;
    std::vector<labels::LabelCandidate> m_candidates;
    std::unordered_map<std::uint64_t, Feature> m_features;  ///< by label id
    std::vector<text::LaidOutText> m_texts;
    std::vector<text::TextDraw> m_screen;
    std::vector<text::WorldTextDraw> m_world;
    std::vector<LabelOccluder> m_occluders;
    std::uint64_t m_frame = 0;
    std::unordered_map<std::uint64_t, glm::vec2> m_sizes;   ///< text extent at scale 1 by id
    glm::mat4 m_projection{1.0f};
};

}  // namespace navmap::render::gl
