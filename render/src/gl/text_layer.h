#pragma once
// Draws label text from the SDF glyph atlas of navmap_text: screen-space labels (bird's-eye)
// and camera-facing, depth-tested world-space labels (snail's view), with fill, dark outline
// and halo (seed 4.5.2). Private to render/.

#include <GLES3/gl3.h>

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "navmap/render/text/glyph_atlas.h"
#include "navmap/render/text/text_draw.h"
#include "shader_program.h"

namespace navmap::render::gl {

struct TextLayerStats {
    std::size_t labels = 0;        ///< labels drawn by the last draw call
    std::size_t glyphs = 0;        ///< glyph quads drawn by the last draw call
    std::size_t atlas_uploads = 0; ///< texture (re)uploads since creation
};

/// Needs a current GLES 3 context on the calling thread (create, use, destroy there). Draws
/// into the bound framebuffer; the caller sets the viewport to `viewport`. Leaves blending off,
/// depth test on and depth writes on, as the map passes expect.
class TextLayer {
public:
    /// Compiles text_sdf.{vert,frag}; throws RenderError. The atlas must outlive the layer; the
    /// layer uploads its changed rows before each draw and clears its dirty range.
    explicit TextLayer(text::GlyphAtlas& atlas);
    ~TextLayer();
    TextLayer(const TextLayer&) = delete;
    TextLayer& operator=(const TextLayer&) = delete;

    /// Labels in screen pixels (origin top left, y down), no depth test.
    void drawScreen(std::span<const text::TextDraw> labels, glm::ivec2 viewport);
    /// Labels at 3D points (in the frame of `view`), facing the camera, tested against the
    /// depth buffer without writing it.
    void drawWorld(std::span<const text::WorldTextDraw> labels, const glm::mat4& view, const glm::mat4& projection,
                   glm::ivec2 viewport);

    [[nodiscard]] const TextLayerStats& stats() const { return m_stats; }

private:
    struct Instance {
        glm::vec4 rect, tex, anchor, params, fill, outline, halo, widths;
    };
    void syncAtlas();
    void appendLabel(std::span<const text::GlyphQuad> quads, const text::TextStyle& style, glm::vec4 anchor,
                     glm::vec4 params, float max_px);
    void draw(bool world, const glm::mat4& view_projection, float focal_y, glm::ivec2 viewport);

    text::GlyphAtlas& m_atlas;
    ShaderProgram m_program;
    GLuint m_texture = 0;
    int m_texture_height = 0;
    std::uint64_t m_uploaded_version = 0;
    GLuint m_vao = 0;
    GLuint m_vbo = 0;
    std::size_t m_vbo_capacity = 0;  // instances
    std::vector<Instance> m_instances;
    TextLayerStats m_stats;
};

}  // namespace navmap::render::gl
