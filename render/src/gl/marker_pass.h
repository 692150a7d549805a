// SPDX-License-Identifier: Apache-2.0
#pragma once
// The vehicle marker: a CCP arrow at the vehicle's position, turned to its heading as seen on
// screen, constant in size, with a dark outline (marker.vert/.frag). Drawn last, over everything.
// Private to render/.

#include <GLES3/gl3.h>

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "frame_context.h"
#include "shader_program.h"

namespace navmap::render::gl {

class MarkerPass {
public:
    /// The marker as it will be drawn: projected anchor, heading on screen and the screen outline.
    struct OnScreen {
        glm::vec4 anchor_clip{0.0f};
        glm::vec2 screen_dir{0.0f, 1.0f};  ///< unit, pixels, y up
        std::vector<glm::vec2> outline;    ///< screen pixels, y down
    };

    /// Compiles the marker program (throws RenderError).
    MarkerPass();
    ~MarkerPass();
    MarkerPass(const MarkerPass&) = delete;
    MarkerPass& operator=(const MarkerPass&) = delete;

    /// Where this frame's marker will be drawn; none without a marker or behind the camera. The
    /// labels keep out of its outline.
    [[nodiscard]] std::optional<OnScreen> place(const FrameContext& ctx) const;
    /// Draws it into ctx.target (depth test off) and reports its outline in ctx.stats.
    void draw(const FrameContext& ctx, const OnScreen& marker);

private:
    ShaderProgram m_program;
    GLuint m_vao = 0;
    GLuint m_vbo = 0;
};

}  // namespace navmap::render::gl
