#pragma once
// Offscreen framebuffer: colour + depth/stencil, multisampled where supported, with a
// single-sampled resolve target that readback reads from. Private to render/.

#include <GLES3/gl3.h>

namespace navmap::render::gl {

class RenderTarget {
public:
    /// samples <= 1 renders straight into the resolve target. Throws RenderError when the
    /// framebuffer is incomplete.
    RenderTarget(int width, int height, int samples);
    ~RenderTarget();
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;

    void bindForDrawing() const;
    /// Resolves MSAA into the single-sampled target and leaves it bound for reading.
    void resolve() const;

    [[nodiscard]] int width() const { return m_width; }
    [[nodiscard]] int height() const { return m_height; }
    [[nodiscard]] int samples() const { return m_samples; }

private:
    int m_width;
    int m_height;
    int m_samples;
    GLuint m_msaa_fbo = 0;
    GLuint m_msaa_color = 0;
    GLuint m_msaa_depth = 0;
    GLuint m_resolve_fbo = 0;
    GLuint m_resolve_color = 0;
    GLuint m_resolve_depth = 0;
};

}  // namespace navmap::render::gl
