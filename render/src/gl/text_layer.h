// SPDX-License-Identifier: Apache-2.0
#pragma once
// Draws label text from the SDF glyph atlas of navmap_text: screen-space labels (bird's-eye)
// and world-space labels lying in planes of the scene, perspective-projected and depth-tested
// (snail's view, seed 5.2.1), with fill, dark outline and halo (seed 4.5.2). Private to render/.

#include <GLES3/gl3.h>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "navmap/render/text/glyph_atlas.h"
#include "shader_program.h"
#include "text/text_draw.h"

namespace navmap::render::gl {

struct TextLayerStats {
    std::size_t labels = 0;         ///< labels drawn by the last draw call
    std::size_t glyphs = 0;         ///< glyph quads drawn by the last draw call
    std::size_t atlas_uploads = 0;  ///< texture (re)uploads since creation
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
    /// Labels in planes of the world (in the frame of `view`), projected with the scene and
    /// tested against the depth buffer without writing it.
    void drawWorld(std::span<const text::WorldTextDraw> labels, const glm::mat4& view, const glm::mat4& projection,
                   glm::ivec2 viewport);

    /// Measures occlusion (labels as drawn by drawWorld with `view` and `projection`): draws each
    /// label's ink (fill and outline) in a colour naming it into a scratch framebuffer that uses
    /// `depth_stencil_rb` (the scene's depth, `samples` as the target) as its depth, once with
    /// no depth test and once with the drawWorld test, and counts pixels per label. Returns
    /// {all, passing}, indexed by label index + 1 (index 0: background). Leaves no framebuffer
    /// bound. Throws RenderError when the scratch framebuffer is incomplete.
    std::pair<std::vector<std::uint64_t>, std::vector<std::uint64_t>> countIdPixels(
        std::span<const text::WorldTextDraw> labels, const glm::mat4& view, const glm::mat4& projection,
        glm::ivec2 viewport, GLuint depth_stencil_rb, int samples);

    [[nodiscard]] const TextLayerStats& stats() const { return m_stats; }

private:
    struct Instance {
        glm::vec4 rect, tex, anchor, params, fill, outline, halo, widths, right, up;
    };
    void syncAtlas();
    void appendLabel(std::span<const text::GlyphQuad> quads, const text::TextStyle& style, glm::vec4 anchor,
                     glm::vec4 params, glm::vec3 right = glm::vec3(0.0f), glm::vec3 up = glm::vec3(0.0f));
    void draw(bool world, const glm::mat4& view_projection, float focal_y, glm::ivec2 viewport);
    void drawInstances(ShaderProgram& program, bool world, const glm::mat4& view_projection, float focal_y,
                       glm::ivec2 viewport);

    text::GlyphAtlas& m_atlas;
    ShaderProgram m_program;
    ShaderProgram m_id_program;  ///< NAVMAP_TEXT_IDS variant, made on first use
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
