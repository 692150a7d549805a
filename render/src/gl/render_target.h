// SPDX-License-Identifier: Apache-2.0
#pragma once
// Offscreen framebuffer: colour + road-intensity mask + depth/stencil, multisampled where
// supported, with single-sampled resolve targets: colour for readback, mask as a texture for
// the screen-space outline pass (seed 3.6.3). Without MSAA nothing is copied: the mask is drawn
// straight into its texture and readback reads the drawing framebuffer (on llvmpipe each of
// those full-screen copies cost about as much as a pass). Private to render/.

#include <GLES3/gl3.h>

#include <cstdint>
#include <vector>

#include "outline_cells.h"

namespace navmap::render::gl {

/// Throws RenderError naming `what` and the status when the bound framebuffer is incomplete.
void checkFramebufferComplete(const char* what);
/// A renderbuffer of `format`, multisampled when samples > 0.
GLuint makeRenderbuffer(GLenum format, int samples, int w, int h);

/// The size of a scratch buffer that users of different sizes take turns with (the renderer's
/// targets render one after another): it grows to the largest width and height asked for and
/// never shrinks. A larger attachment is fine in ES 3.0 (a framebuffer's area is the
/// intersection of its attachments).
struct ScratchSize {
    int width = 0, height = 0;
    /// False when w x h fits; else grows to cover it and returns true (make the buffer anew).
    bool grow(int w, int h) {
        if (w <= width && h <= height) return false;
        width = w > width ? w : width;
        height = h > height ? h : height;
        return true;
    }
};

class RenderTarget {
public:
    /// The sample count a target asked for `samples` gets (0: no MSAA; clamped to GL_MAX_SAMPLES).
    static int effectiveSamples(int samples);

    /// samples <= 1 disables MSAA. `shared_depth_stencil` (0: the target makes its own): a
    /// GL_DEPTH24_STENCIL8 renderbuffer with effectiveSamples(samples) samples and at least
    /// width x height, which the target uses but does not own (see attachDepthStencil()).
    /// Throws RenderError when a framebuffer is incomplete.
    RenderTarget(int width, int height, int samples, GLuint shared_depth_stencil = 0);
    ~RenderTarget();
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;

    /// Binds the drawing framebuffer; `with_mask` routes fragment output 1 to the mask. Without
    /// it the framebuffer bound has the colour and depth/stencil but not the mask attached.
    void bindForDrawing(bool with_mask = false) const;
    /// Clears colour (to `rgb`), mask (to 0), depth and stencil.
    void clear(float r, float g, float b) const;
    /// Makes maskTexture() hold the mask (a resolve with MSAA, nothing without) and binds for
    /// drawing without the mask, so a pass can sample maskTexture() (no feedback loop).
    void resolveMask() const;
    /// Resolves colour into the single-sampled target and leaves it bound for reading.
    void resolve() const;
    /// Attaches another shared depth/stencil renderbuffer (same format and samples, at least the
    /// target's size), e.g. a larger one after a larger target was added. Throws RenderError.
    void attachDepthStencil(GLuint shared_depth_stencil);

    [[nodiscard]] GLuint maskTexture() const { return m_mask_texture; }
    /// The road mask bit-packed for the outline filter (outline_pack.frag): an R16UI texture of
    /// packedMaskWidth() x height, made on the first call. Binds its framebuffer for drawing, with
    /// the viewport over it, and returns the texture.
    GLuint bindPackedMask() const;
    [[nodiscard]] int packedMaskWidth() const { return navmap::render::packedMaskWidth(m_width); }
    /// Whether readMask() can read the road mask: no MSAA, and the driver reads the mask's format
    /// as one byte per pixel (ES 3.0 guarantees only RGBA bytes; Mesa offers single bytes for R8).
    [[nodiscard]] bool readsMaskBytes() const;
    /// Reads the road mask into `bytes` (width x height, the bottom row first). Needs readsMaskBytes().
    void readMask(std::vector<std::uint8_t>& bytes) const;
    /// Uploads packedMaskWidth() x height `texels` (outlineEdges' layout) into the packed mask's
    /// texture, made on the first call, and returns it. Binds no framebuffer.
    GLuint uploadPackedMask(const std::uint16_t* texels) const;
    /// The drawing framebuffer and its depth-stencil renderbuffer: the occlusion effects (glowing
    /// roads, label aura) attach the same depth to their own framebuffers and blit from it.
    [[nodiscard]] GLuint drawFramebuffer() const { return m_draw_fbo; }
    [[nodiscard]] GLuint depthStencilRenderbuffer() const { return m_depth_rb; }
    [[nodiscard]] int width() const { return m_width; }
    [[nodiscard]] int height() const { return m_height; }
    [[nodiscard]] int samples() const { return m_samples; }

private:
    void makePackedMask() const;  // the packed mask's texture, on the first call

    int m_width;
    int m_height;
    int m_samples;
    mutable int m_reads_mask_bytes = -1;  // readsMaskBytes(), asked once (-1: not yet)
    GLuint m_draw_fbo = 0;
    GLuint m_color_rb = 0;
    GLuint m_mask_rb = 0;
    GLuint m_depth_rb = 0;
    bool m_owns_depth = true;  // false: a depth/stencil buffer shared by the renderer's targets
    GLuint m_resolve_fbo = 0;
    GLuint m_resolve_color = 0;
    GLuint m_mask_fbo = 0;  // MSAA only: resolve target of the mask
    GLuint m_mask_texture = 0;
    GLuint m_composite_fbo = 0;           // colour + depth/stencil, no mask
    mutable GLuint m_packed_texture = 0;  // bindPackedMask(), made on first use
    mutable GLuint m_packed_fbo = 0;
};

}  // namespace navmap::render::gl
