// SPDX-License-Identifier: Apache-2.0
#pragma once
// The renderer's public face: create a backend, give it a scene, render frames offscreen and
// read them back. No GL or EGL type appears here (render/README.md).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "navmap/render/camera.h"
#include "navmap/render/dmabuf_probe.h"
#include "navmap/render/heightfield.h"
#include "navmap/render/image.h"
#include "navmap/render/map_frame.h"

namespace navmap::render {

/// Raised at setup when no usable EGL/GLES context can be made or a shader does not compile.
/// The message names what is missing (extension, platform, shader file and line).
class RenderError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Which EGL platform provides the display.
enum class Platform {
    Auto,         ///< a hardware EGL device if one exists, else Mesa surfaceless, else any EGL device
    Surfaceless,  ///< EGL_MESA_platform_surfaceless (Mesa: llvmpipe or any DRM GPU)
    Device,       ///< EGL_EXT_platform_device (NVIDIA and Mesa devices)
};

/// Parses "auto", "surfaceless" or "device"; nullopt otherwise.
std::optional<Platform> parsePlatform(const std::string& name);
const char* platformName(Platform platform);

struct RendererOptions {
    /// Platform::Auto consults the environment variable NAVMAP_EGL_PLATFORM first.
    Platform platform = Platform::Auto;
    int width = 1280;
    int height = 480;
    /// MSAA samples: 0 or 1 disables, clamped to what the driver offers; -1 (auto) uses 4 on
    /// GPUs and none on software rasterizers (llvmpipe), where it doubles the frame time.
    int msaa_samples = -1;
    /// Pixel-pack buffers in flight per target for asynchronous readback. 1: no buffer, readAsync
    /// reads the frame straight into its image and collectReadbacks hands it out. 0 (automatic): 1
    /// on software rasterizers (llvmpipe waits for the rasterization in glReadPixels either way),
    /// 2 on GPUs.
    int readback_ring = 3;
    /// Tiles prepared and uploaded per map frame at most (0 = no limit). Tiles over the budget
    /// are drawn from the next frames on.
    int max_tile_uploads_per_frame = 0;
    /// GPU tile resources kept for tiles not drawn recently.
    int tile_resource_cache = 160;
    /// Measure each pass (adds a glFinish per pass; benchmarks only).
    bool profile_passes = false;
    /// Weights of the synthetic orthoimage network (docs/orthoimage.md, data/ortho/ortho-mlp.nnw),
    /// read when the renderer is made (start-up, never in a frame; a regular file of at most the
    /// format's size, opened without blocking) and uploaded when MapStyle::ground first asks for
    /// the orthoimage. Empty or unusable: the ground stays land cover and
    /// MapFrameStats::ortho_problem says why, once, when the orthoimage is first asked for; never
    /// thrown.
    std::string ortho_weights;
    /// Pixels of orthoimage network work per map frame at most (seed 6.6.2: an image is made in
    /// bands of rows over several frames, its tile showing the land cover meanwhile); 0: each
    /// image is finished in the frame that starts it.
    std::size_t ortho_pixels_per_frame = 0;
    /// A directory for linked shader programs as the driver's binaries (glProgramBinary): a
    /// later renderer on the same driver loads them instead of compiling the GLSL; a binary the
    /// driver rejects is compiled again and replaced. Empty: no cache. The driver must offer a
    /// binary format (Mesa does only while its own shader cache is on).
    std::string program_cache_dir;
    /// Pay at creation for the driver code that the first map frame would otherwise wait for
    /// (the land-cover raster's multisample resolve and mipmaps: about 300 ms of shader JIT on
    /// llvmpipe). For a daemon's start-up, where creation overlaps other work; tests and tools that
    /// make many renderers leave it off.
    bool warm_up = false;
};

/// The renderer's program binary cache (RendererOptions::program_cache_dir), since its creation.
struct ProgramCacheStats {
    std::string dir;                 ///< empty: no cache
    std::string problem;             ///< why the configured cache is off; empty: in use
    std::uint64_t loaded = 0;        ///< programs loaded from binaries
    std::uint64_t compiled = 0;      ///< programs compiled from GLSL (then stored)
    std::uint64_t rejected = 0;      ///< binaries the driver (or the file check) refused: compiled instead
    std::uint64_t stored = 0;        ///< binaries written
    std::uint64_t write_errors = 0;  ///< binaries that could not be written
};

/// What the backend runs on, for logs and status.
struct DeviceInfo {
    std::string backend;   ///< "gles" or "noop"
    std::string platform;  ///< EGL platform used
    std::string vendor;
    std::string renderer;
    std::string version;
    int gles_major = 0;
    int gles_minor = 0;
    int msaa_samples = 0;   ///< samples of the offscreen target actually used
    bool software = false;  ///< a software rasterizer (llvmpipe, softpipe, swrast)
    /// Optional features turned off on this context, each "what (why): what is done instead"
    /// (docs/gles-profile.md); empty when nothing is missing.
    std::vector<std::string> features_off;
    /// The context was made robust (EGL_EXT_create_context_robustness, lose context on reset), so
    /// a GPU reset is reported instead of going unnoticed.
    bool robust_context = false;
    /// Times the context was found lost or reset (glGetGraphicsResetStatus, checked at the start
    /// of each frame) and made anew: targets, programs and tiles re-created and re-uploaded, the
    /// frame rendered on the new one (docs/gles-profile.md "Lost contexts").
    int context_resets = 0;
    /// Whether the display could export frames as dma-bufs, and why not (dmabuf_probe.h);
    /// probed once when the context is made. The no-op backend: unavailable.
    DmabufCapability dmabuf;
};

/// Terrain shading parameters (kept separate so the shading is pluggable, docs/architecture.md "Rendering").
struct TerrainStyle {
    glm::vec3 light_dir{-0.5f, 0.6f, 0.62f};  ///< towards the light (north-west, as cartographers light relief)
    glm::vec3 sky_color{0.62f, 0.75f, 0.90f};
    float fog_start_m = 8000.0f;
    float fog_end_m = 45000.0f;
};

/// A frame copied on the GPU into one of a target's exported buffers (Renderer::exportFrame;
/// docs/frame-protocol.md "dma-buf frames"): rows top first, like a read-back Image.
struct DmabufFrame {
    int buffer = -1;  ///< the buffer's index in the target's pool, 0..kDmabufBuffers-1
    /// Which allocation of that index: it changes when the buffer is made anew (a resize, a new
    /// context), and a client needs the new fd then.
    std::uint64_t generation = 0;
    int fd = -1;                 ///< the buffer's dma-buf; the renderer owns it (dup it to keep or pass it on)
    std::uint32_t fourcc = 0;    ///< DRM fourcc: DRM_FORMAT_ABGR8888 (RGBA8 bytes)
    std::uint64_t modifier = 0;  ///< DRM format modifier (DRM_FORMAT_MOD_LINEAR = 0)
    std::uint32_t stride = 0;    ///< bytes per row of plane 0
    std::uint32_t offset = 0;    ///< plane 0's offset in the buffer
    int width = 0;
    int height = 0;
    /// A sync fence fd that signals when the frame is in the buffer (EGL_ANDROID_native_fence_sync);
    /// the caller owns it. -1: the frame was finished (glFinish) before exportFrame returned.
    int fence_fd = -1;
};

/// Buffers per target that exportFrame() cycles through.
inline constexpr int kDmabufBuffers = 4;

/// Premultiplied RGBA8 pixels blended over an exported frame at (x, y) (rows top first), e.g. the
/// map data attribution a read-back frame gets on the CPU. `id` names the pixels: the renderer
/// uploads them again only when it changes.
struct FrameOverlay {
    const Image* image = nullptr;
    int x = 0;
    int y = 0;
    std::uint64_t id = 0;
};

/// A frame read back from the GPU, tagged with the caller's sequence number.
struct Frame {
    std::uint64_t sequence = 0;
    Image image;
};

/// A display's offscreen target in a Renderer: returned by Renderer::primaryTarget() and
/// Renderer::addTarget(), valid until Renderer::removeTarget(). A default-constructed handle names
/// no target. Handles are values: copy them freely; only the renderer that made one knows it.
class TargetHandle {
public:
    TargetHandle() = default;
    /// Small and stable for the target's life (logs, maps keyed by target).
    [[nodiscard]] int id() const { return m_id; }
    [[nodiscard]] bool valid() const { return m_id >= 0; }
    friend bool operator==(TargetHandle, TargetHandle) = default;

private:
    friend class Renderer;
    explicit TargetHandle(int id) : m_id(id) {}
    int m_id = -1;
};

/// An offscreen renderer bound to the thread that created it (EGL context current there).
/// Not thread-safe: create, use and destroy it on one thread.
///
/// One renderer serves several displays: each has its own offscreen target (size, readback
/// ring, label layout state), all share the one context, the shaders and the GPU resources of
/// the tiles. Every call that draws into or reads from a target names it by its TargetHandle;
/// there is no current target. The primary target (options.width x options.height) exists from
/// the start and stays; addTarget() makes more. The calls without a handle act on the primary
/// target (single-display use). A handle of another renderer or of a removed target is a
/// programming error: RenderError. mapStats() describes the last renderMap call.
class Renderer {
public:
    /// Creates the OpenGL ES backend. Throws RenderError with a clear reason if EGL/GLES is unusable.
    static std::unique_ptr<Renderer> create(const RendererOptions& options);
    /// Creates the no-op backend: same API, no GL; frames come back blank (sky colour).
    static std::unique_ptr<Renderer> createNoop(const RendererOptions& options);

    virtual ~Renderer() = default;
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    [[nodiscard]] virtual const DeviceInfo& device() const = 0;

    /// The target made with the renderer (options.width x options.height); it cannot be removed.
    [[nodiscard]] TargetHandle primaryTarget() const { return TargetHandle(0); }
    /// Adds an offscreen target of its own size (own readback ring and label layout) and returns
    /// its handle. Throws RenderError for an invalid size.
    virtual TargetHandle addTarget(int width, int height) = 0;
    /// Frees `target` (its pending readbacks are dropped). Returns false for the primary target
    /// and for a handle that names no target (any more).
    virtual bool removeTarget(TargetHandle target) = 0;
    [[nodiscard]] virtual std::size_t targetCount() const = 0;

    /// Size of `target`.
    [[nodiscard]] virtual int width(TargetHandle target) const = 0;
    [[nodiscard]] virtual int height(TargetHandle target) const = 0;
    /// Changes the size of `target` (its pending readbacks are completed first).
    virtual void resize(TargetHandle target, int width, int height) = 0;
    /// Uploads a terrain mesh, replacing the previous one.
    virtual void setTerrain(const HeightfieldMesh& mesh) = 0;
    virtual void setTerrainStyle(const TerrainStyle& style) = 0;

    /// Renders one frame of the terrain-only scene (setTerrain) into `target`.
    virtual void render(TargetHandle target, const Camera& camera) = 0;

    virtual void setMapStyle(const MapStyle& style) = 0;
    /// Renders one map frame from tiles into `target`: terrain with land cover, draped roads with
    /// casing and outlines, buildings, route and vehicle marker ([architecture.md](architecture.md) "Render passes").
    /// The target's label layout continues from its own previous frame.
    virtual void renderMap(TargetHandle target, const MapFrame& frame) = 0;
    [[nodiscard]] virtual const MapFrameStats& mapStats() const = 0;
    /// The program binary cache's counters (empty `dir` when there is none, as with the no-op renderer).
    [[nodiscard]] virtual ProgramCacheStats programCache() const { return {}; }
    /// Blocks until the GPU has finished all submitted work (for timing).
    virtual void finish() = 0;

    /// Synchronous readback of the last frame rendered into `target`.
    virtual Image readSync(TargetHandle target) = 0;
    /// Starts an asynchronous readback of the last frame rendered into `target` into the next
    /// buffer of its ring. When the ring is full, the oldest readback is completed and returned;
    /// by then it is ring-1 frames old, so the wait is normally zero.
    virtual std::optional<Frame> readAsync(TargetHandle target, std::uint64_t sequence) = 0;
    /// Returns `target`'s asynchronous readbacks that have already finished, oldest first,
    /// without waiting (the frame loop calls it after rendering, so frames leave in the same tick).
    virtual std::vector<Frame> collectReadbacks(TargetHandle target) = 0;
    /// Completes and returns every pending asynchronous readback of `target`, oldest first.
    virtual std::vector<Frame> drainReadbacks(TargetHandle target) = 0;

    /// Copies the last frame rendered into `target` into a free buffer of the target's pool of
    /// exported dma-bufs (made on the first call, kDmabufBuffers of them), on the GPU: no CPU copy.
    /// Bit i of `busy` set: buffer i is still in use by a client and is not written. `overlay`
    /// (optional) is blended over the copy. Nothing (nullopt) when the device cannot export
    /// (device().dmabuf says why) or every buffer is busy.
    virtual std::optional<DmabufFrame> exportFrame(TargetHandle target, std::uint32_t busy,
                                                   const FrameOverlay* overlay = nullptr) {
        (void)target, (void)busy, (void)overlay;
        return std::nullopt;
    }

    /// The same on the primary target.
    [[nodiscard]] int width() const { return width(primaryTarget()); }
    [[nodiscard]] int height() const { return height(primaryTarget()); }
    void resize(int width, int height) { resize(primaryTarget(), width, height); }
    void render(const Camera& camera) { render(primaryTarget(), camera); }
    void renderMap(const MapFrame& frame) { renderMap(primaryTarget(), frame); }
    Image readSync() { return readSync(primaryTarget()); }
    std::optional<Frame> readAsync(std::uint64_t sequence) { return readAsync(primaryTarget(), sequence); }
    std::vector<Frame> collectReadbacks() { return collectReadbacks(primaryTarget()); }
    std::vector<Frame> drainReadbacks() { return drainReadbacks(primaryTarget()); }

protected:
    Renderer() = default;
    /// For the backends: the handle of their target `id` (0: the primary target).
    [[nodiscard]] static TargetHandle handle(int id) { return TargetHandle(id); }
};

}  // namespace navmap::render
