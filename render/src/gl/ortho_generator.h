// SPDX-License-Identifier: Apache-2.0
#pragma once
// Synthetic orthoimages of tiles on the GPU (seed 6.6.2): the compressed input vectors are made on
// a worker thread from the tile's layers (map::ortho::OrthoTileSampler), the network runs in a
// fragment shader over them (ortho_mlp.frag) into the basic orthoimage, which is then copied into
// the tile's mipmapped texture. An image is started when its tile is uploaded and worked on in
// bands of rows within a per-frame pixel budget, so no frame waits for a whole image; the tile
// shows its land cover until its image is ready. The procedural detail of seed 6.7 (fields, roofs,
// and plants where asked for: OrthoDetail) is made on the same worker and drawn over the copied
// basic layer after the last band, taking its colour from it: with a budget in steps of its own
// (copy and fields, plant slices, roofs and mipmaps), one per frame. The render thread only
// uploads and draws. Private to render/.

#include <GLES3/gl3.h>

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/map/ortho/ortho_network.h"
#include "navmap/map/tile.h"
#include "ortho_detail.h"
#include "shader_program.h"

namespace navmap::render::gl {

class OrthoGenerator {
public:
    /// Uploads the network's weights. Throws RenderError when they do not fit the driver's uniform
    /// blocks or the network's inputs are not this build's encoding.
    explicit OrthoGenerator(const map::ortho::OrthoNetwork& network);
    ~OrthoGenerator();
    OrthoGenerator(const OrthoGenerator&) = delete;
    OrthoGenerator& operator=(const OrthoGenerator&) = delete;

    struct Request {
        std::shared_ptr<const map::Tile> tile;  ///< kept while the image is pending; needs ortho layers
        glm::vec2 offset{0.0f};                 ///< the square [offset, offset + extent] of the tile (m)
        float extent = 0.0f;
        int size = 256;           ///< pixels per side (a power of two)
        bool details = true;      ///< fields and roofs (seed 6.7.2, 6.7.3)
        bool vegetation = false;  ///< plants (seed 6.7.1): leaf tiles, which are seen at close range
    };
    /// A new RGB565 texture (size^2, mipmapped) whose image step() generates; sample it only once
    /// ready() says so. Returns 0 and sets `problem` when the tile's layers cannot be sampled
    /// (map::ortho::orthoLayersProblem) or the size is not a power of two in 1..4096.
    GLuint start(const Request& request, std::string& problem);
    /// Works on the pending images, oldest first (0: until none is left, waiting for the worker).
    /// With a budget, a call either runs bands of the network pass for at most `pixel_budget`
    /// pixels (at least a band of 16 rows) or does one step of an image's finish (the copy and the
    /// fields, a slice of kPlantsPerStep plants, the roofs and the mipmaps); an image whose input
    /// vectors or detail the worker has not made yet waits for a later call instead of blocking
    /// this one. Leaves the framebuffer binding at 0.
    void step(std::size_t pixel_budget);
    static constexpr std::size_t kPlantsPerStep = 8192;
    /// False for an image still pending and for one whose input vectors could not be made (the
    /// worker threw: out of memory), which then never becomes ready (its tile keeps the land cover).
    [[nodiscard]] bool ready(GLuint texture) const;
    /// Forgets a pending or failed image (its tile was evicted); the caller deletes the texture.
    void cancel(GLuint texture);
    [[nodiscard]] std::size_t pending() const { return m_jobs.size(); }

    /// The network pass alone over `inputs` (size^2, row 0 first), read back as RGBA8 (tests: GPU
    /// against the CPU reference; the benchmark). Blocks.
    std::vector<std::uint8_t> runNetwork(std::span<const map::ortho::OrthoInput> inputs, int size);
    /// A finished image read back as RGBA8, row 0 south (tests, the benchmark). Blocks.
    std::vector<std::uint8_t> read(GLuint texture, int size);

    struct Timings {
        double encode_ms = 0;   ///< input vectors on the CPU (on the worker thread)
        double network_ms = 0;  ///< upload and network pass (GL calls; the GPU work completes later)
        double finish_ms = 0;   ///< copy, detail and mipmaps (GL calls)
        std::size_t images = 0, pixels = 0;
        std::size_t detail_failures = 0;  ///< images left without detail: its worker threw
        std::size_t input_failures = 0;   ///< images never made: the worker threw on their inputs
    };
    /// Accumulated since construction.
    [[nodiscard]] const Timings& timings() const { return m_timings; }
    /// The procedural detail's share (CPU grid and simulation, draw calls), accumulated.
    [[nodiscard]] const OrthoDetail::Timings& detailTimings() const { return m_detail.timings(); }

    /// Tests: images started from now on show the field parcels alone, white on black (their drawn
    /// area).
    void setFieldMaskOnly(bool on) { m_field_mask_only = on; }

private:
    /// An image's input vectors as the planes of the inputs texture (plane k: pairs 2k and 2k + 1
    /// of every pixel, RGBA8UI), made by the worker.
    struct Inputs {
        std::vector<std::uint8_t> planes;
        double encode_ms = 0;
    };
    enum class Stage { Bands, CopyAndFields, Plants, Roofs };
    struct Job {
        Request request;
        GLuint texture = 0;
        int next_row = 0;
        bool field_mask_only = false;
        Stage stage = Stage::Bands;
        std::size_t plants_drawn = 0;
        bool inputs_queued = false;
        std::future<Inputs> inputs_made;                        // by the worker, queued when the job is near
        std::shared_ptr<const Inputs> inputs;                   // taken from it; dropped after the last band
        std::future<OrthoDetail::Geometry> detail;              // by the worker, queued at start()
        std::shared_ptr<const OrthoDetail::Geometry> geometry;  // taken from it
        std::shared_ptr<std::atomic<bool>> cancelled;           // tells the worker to skip it
    };
    void ensureScratch(int size);
    void queueInputs(Job& job);
    void enqueue(std::function<void()> task, bool first);
    void uploadPlanes(const std::uint8_t* planes, int size, int row0, int row1);
    void drawNetwork(int size, int row0, int row1);
    void bindImage(const Job& job);
    bool finishStep(Job& job, bool all);
    void workerLoop();

    ShaderProgram m_network, m_copy;
    OrthoDetail m_detail;
    bool m_field_mask_only = false;
    GLuint m_weights = 0;  // uniform buffer (OrthoWeights)
    GLuint m_inputs = 0;   // RGBA8UI, size x (size * texels per pixel)
    GLuint m_basic = 0;    // RGBA8, the network's output
    GLuint m_fbo = 0;
    GLuint m_empty_vao = 0;
    int m_scratch_size = 0;
    std::deque<Job> m_jobs;
    std::vector<GLuint> m_failed;  // textures whose inputs could not be made
    Timings m_timings;
    // The CPU work beside the render thread: the detail (OrthoDetail::build) in start() order, the
    // input vectors of the next images ahead of it.
    std::mutex m_mutex;
    std::condition_variable m_wake;
    std::deque<std::function<void()>> m_queue;
    bool m_stop = false;
    std::thread m_worker;  // started with the first image
};

}  // namespace navmap::render::gl
