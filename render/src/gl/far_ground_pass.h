// SPDX-License-Identifier: Apache-2.0
#pragma once
// The ground beyond the store's data (docs/rendering.md "Beyond the data"): where no tile was
// drawn below the horizon, a level plane at the lowest height of the drawn terrain continues in
// MapStyle::far_ground_color, fogged like the terrain, so no view shows the sky below the
// horizon. The screen below the horizon as one polygon at the far depth, after terrain and
// buildings: the depth test (early: no depth writes, no discard) leaves it only the pixels nothing
// covered. Private to render/.

#include <GLES3/gl3.h>

#include "frame_context.h"
#include "shader_program.h"

namespace navmap::render::gl {

class FarGroundPass {
public:
    /// Compiles the program (throws RenderError).
    FarGroundPass();
    ~FarGroundPass();
    FarGroundPass(const FarGroundPass&) = delete;
    FarGroundPass& operator=(const FarGroundPass&) = delete;

    /// Fills what is still clear below the horizon of ctx.tiles' lowest surface. Expects the
    /// depth buffer of the terrain and buildings; leaves depth writes off and the test LEQUAL.
    void draw(const FrameContext& ctx);

private:
    ShaderProgram m_program;
    GLuint m_vao = 0;
};

}  // namespace navmap::render::gl
