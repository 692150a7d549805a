// SPDX-License-Identifier: Apache-2.0
#pragma once
// The label pass of MapRenderer per display target: each target keeps its own LabelPass (the
// layout's temporal coherence, seed 4.3, continues from that display's previous frame), all share
// the fonts and glyph atlas (LabelText). Feeds LabelPass the frame's tiles and draws into the
// frame's target. Private to render/.

#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "frame_context.h"
#include "label_pass.h"

namespace navmap::render::gl {

class MapLabelPass {
public:
    MapLabelPass() = default;
    MapLabelPass(const MapLabelPass&) = delete;
    MapLabelPass& operator=(const MapLabelPass&) = delete;

    /// seed ch. 4: lays out this frame's labels for ctx.target_id, out of `keep_out` (the
    /// marker's screen outline, pixels, y down). Creates the target's label state on its first
    /// frame with labels.
    void layout(const FrameContext& ctx, std::span<const glm::vec2> keep_out);
    /// Start-up (RendererOptions::warm_up): loads the fonts and compiles the text shaders now, and
    /// starts making the Latin glyphs on a background thread, instead of in the first frame.
    void warmUp();
    /// The labels laid out by layout(), as the label aura sees them (seed 5.5.1); empty without
    /// labels this frame.
    [[nodiscard]] std::span<const LabelOccluder> occluders(const FrameContext& ctx) const;
    /// Draws the labels laid out by layout() into ctx.target and, when the layers ask, measures
    /// how much of them the scene hides.
    void draw(const FrameContext& ctx);
    /// Forgets display `target_id`'s label state.
    void dropTarget(int target_id) { m_passes.erase(target_id); }

private:
    std::shared_ptr<LabelText> m_text;                             // fonts and glyph atlas of every target's label pass
    std::unordered_map<int, std::unique_ptr<LabelPass>> m_passes;  // by target
    LabelPass* m_current = nullptr;                                // this frame's (layout())
    std::vector<TileLabels> m_tile_labels;
};

}  // namespace navmap::render::gl
