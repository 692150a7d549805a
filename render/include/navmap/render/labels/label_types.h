// SPDX-License-Identifier: Apache-2.0
#pragma once
// Plain data exchanged between the renderer and the label layout (seed chapter 4).
// Coordinates are screen pixels: origin top-left, x to the right, y down.

#include <cstdint>

#include <glm/vec2.hpp>

#include "navmap/render/labels/oriented_box.h"

namespace navmap::render::labels {

/// Feature category of a label (seed 4.4.2) and the behavior it gets (seed 4.4.5).
enum class LabelKind : std::uint8_t {
    Point,   ///< four-position model, free behavior (eq. 4.7)
    Area,    ///< four-position model at the projected barycenter, free behavior, always horizontal
    Line,    ///< three candidates along the projected segment, line behavior (eq. 4.10-4.16)
    Circle,  ///< circles around its anchor at a radius (eq. 4.17)
};

/// Life cycle of a label inside the layout.
enum class LabelState : std::uint8_t {
    Pending,    ///< known, waiting for its turn in the placement queue
    Waiting,    ///< no free candidate or removed; retries when its timer expires (seed 4.4.3, 4.5.3)
    FadingIn,   ///< placed, alpha rising (seed 4.4.3: smoothly alpha-blended into the layout)
    Visible,    ///< placed, alpha 1
    FadingOut,  ///< removed or gone from the input, alpha falling
};

/// Why a label was taken out of the layout (counted in LayoutStats).
enum class RemovalReason : std::uint8_t {
    None,
    Gone,         ///< the caller no longer supplies it (off screen, culled)
    Speed,        ///< seed 4.5.3 speed-based removal
    Constricted,  ///< seed 4.5.3: the forces on it cancel out
    Overlap,      ///< its box kept overlapping a more important label
    OffScreen,    ///< its text box left the viewport (the camera turned): it would be cut
    /// Over a keep-out area (marker, route, arrow) in a drawn frame; also counted in
    /// LayoutStats::removed_overlap. As PlacedLabel::held_by: a keep-out area blocked its placement.
    KeepOut,
};

/// One label candidate for the current frame, already projected by the renderer.
/// Size is the text extent at scale 1 (from the text metrics), in pixels.
struct LabelCandidate {
    std::uint64_t id = 0;   ///< stable feature id; unique within one frame
    float priority = 0.0F;  ///< importance in [0, 1]; higher is placed first and is heavier
    LabelKind kind = LabelKind::Point;
    glm::vec2 anchor{0.0F};   ///< projected anchor p'_i (point, area barycenter, line center)
    float depth = 0.0F;       ///< view distance of the anchor in metres; <= 0 disables depth scaling
    glm::vec2 size{0.0F};     ///< label width and height in pixels at scale 1
    glm::vec2 line_p0{0.0F};  ///< Line: projected longest straight segment s'_line (seed 4.4.2)
    glm::vec2 line_p1{0.0F};
    float circle_radius = 0.0F;  ///< Circle: radius r of eq. 4.17 in pixels; <= 0 picks one from the size
    /// Cap height of the text at scale 1, px: depth scaling never shrinks it below
    /// LayoutParams::min_cap_height_px (seed 4.3.3's readable minimum). <= 0: taken as 0.7 x size.y.
    float cap_height = 0.0F;
    /// World-space labels (seed 5.2.1): the text's baseline direction on screen as projected, a
    /// unit vector. When non-zero the box keeps this axis (no rotation rule, no turning) and
    /// `size` is already the projected size (give depth <= 0: no depth scaling).
    glm::vec2 axis{0.0F};
    /// The label stands on its anchor in the 3D world (world-space text on a road or a sign at a
    /// place): no candidate position lies below the anchor, which would sink it into the ground.
    bool upright = false;
};

/// Camera state that matters to the layout.
struct CameraState {
    /// Angle between the camera look direction and the ground normal, degrees
    /// (0 = looking straight down). Line labels are rotated along their segment only while
    /// the view is not too oblique (seed 4.3.3, 4.4.3).
    float tilt_deg = 0.0F;
    /// Viewport in pixels; candidates must lie inside it. 0 x 0 means unbounded.
    glm::vec2 viewport{0.0F};
    /// Depth at which text has scale 1 (seed 4.3.3 depth scaling), metres: the renderer passes
    /// the camera's look-at distance, so the labels at the center of attention have their design
    /// size whatever the zoom. <= 0: LayoutParams::depth_reference_m.
    float depth_reference_m = 0.0F;
};

/// One label in the layout output.
struct PlacedLabel {
    std::uint64_t id = 0;
    LabelKind kind = LabelKind::Point;
    LabelState state = LabelState::Visible;
    OrientedBox box;                             ///< the text box (scaled, without buffer zone), screen pixels
    glm::vec2 anchor{0.0F};                      ///< the projected anchor it belongs to
    float alpha = 0.0F;                          ///< fade in [0, 1]
    float scale = 1.0F;                          ///< depth scale applied to the text (seed 4.3.3)
    std::uint8_t candidate = 0;                  ///< chosen candidate position (0 = best association)
    RemovalReason reason = RemovalReason::None;  ///< FadingOut: why it was taken out
    /// FadingIn and Visible: what kept it out of the layout before this placement (what its
    /// appearance ends): the reason of its last removal, or of its last failed placement attempt
    /// (OffScreen: none in the viewport or staying in it, KeepOut, Overlap: other labels' zones); None
    /// when placed at its first attempt.
    RemovalReason held_by = RemovalReason::None;
};

}  // namespace navmap::render::labels
