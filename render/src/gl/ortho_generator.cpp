// SPDX-License-Identifier: Apache-2.0
#include "ortho_generator.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <exception>
#include <future>
#include <span>

#include "frame_context.h"
#include "gl/gl_work.h"
#include "navmap/map/ortho/tile_sampler.h"
#include "navmap/render/renderer.h"

namespace navmap::render::gl {

namespace {

namespace mo = map::ortho;
using mo::OrthoInput;

constexpr int kTexels = (mo::kOrthoActive + 1) / 2;  // texels of two (node, value) pairs per pixel
constexpr int kBandRows = 16;                        // rows per band at least
constexpr int kEncodeRows = 64;                      // rows the worker encodes at a time
constexpr std::size_t kInputsAhead = 2;              // images whose input vectors are made ahead

std::size_t planeBytes(int size) { return static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 4; }

// Rows [row0, row1) of input vectors into the planes of the inputs texture: plane k holds pairs 2k
// and 2k + 1 of every pixel, its rows at k * size.
void packPlanes(std::span<const OrthoInput> rows, int size, int row0, std::uint8_t* planes) {
    for (int k = 0; k < kTexels; ++k) {
        std::uint8_t* dst = planes + static_cast<std::size_t>(k) * planeBytes(size) +
                            static_cast<std::size_t>(row0) * static_cast<std::size_t>(size) * 4;
        for (std::size_t p = 0; p < rows.size(); ++p) {
            const OrthoInput& in = rows[p];
            for (std::size_t b = 0; b < 4; ++b) {
                const std::size_t pair_byte = 4 * static_cast<std::size_t>(k) + b;
                dst[p * 4 + b] = pair_byte < in.pairs.size() ? in.pairs[pair_byte] : 0;
            }
        }
    }
}

std::string defines(int hidden4) {
    return "#define NAVMAP_ORTHO_INPUTS " + std::to_string(mo::kOrthoInputs) + "\n#define NAVMAP_ORTHO_HIDDEN4 " +
           std::to_string(hidden4) + "\n#define NAVMAP_ORTHO_TEXELS " + std::to_string(kTexels) + "\n";
}

int hidden4(const mo::OrthoNetwork& net) { return (net.hidden + 3) / 4; }

}  // namespace

OrthoGenerator::OrthoGenerator(const mo::OrthoNetwork& net)
    : m_network(ShaderProgram::fromEmbedded("ortho_screen.vert", "ortho_mlp.frag", defines(hidden4(net)))),
      m_copy(ShaderProgram::fromEmbedded("ortho_screen.vert", "ortho_copy.frag")) {
    if (net.inputs != mo::kOrthoInputs || net.hidden < 1 || net.w0.size() != std::size_t(net.inputs) * net.hidden ||
        net.b0.size() != std::size_t(net.hidden) || net.w1.size() != std::size_t(net.hidden) * 3) {
        throw RenderError("orthoimage network of " + std::to_string(net.inputs) + " inputs and " +
                          std::to_string(net.hidden) + " hidden neurons does not fit this build's " +
                          std::to_string(mo::kOrthoInputs) + " inputs");
    }
    // The weights as std140 vec4 arrays: w0 rows (hidden padded to a multiple of 4 with zero
    // weights, whose sigmoid(0) then meets zero output weights), b0, w1 per output channel, b1.
    const int h4 = hidden4(net), h = net.hidden, n = net.inputs;
    std::vector<float> block(static_cast<std::size_t>((n * h4 + h4 + 3 * h4 + 1) * 4), 0.0f);
    auto at = [](int i) { return static_cast<std::size_t>(i); };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < h; ++j) block[at(i * h4 * 4 + j)] = net.w0[at(i * h + j)];
    }
    const std::size_t b0 = at(n * h4 * 4), w1 = b0 + at(h4 * 4), b1 = w1 + at(3 * h4 * 4);
    for (int j = 0; j < h; ++j) {
        block[b0 + at(j)] = net.b0[at(j)];
        for (int c = 0; c < 3; ++c) block[w1 + at(c * h4 * 4 + j)] = net.w1[at(j * 3 + c)];
    }
    for (int c = 0; c < 3; ++c) block[b1 + at(c)] = net.b1[at(c)];
    GLint max_block = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    const auto bytes = static_cast<GLsizeiptr>(block.size() * sizeof(float));
    if (bytes > max_block) {
        throw RenderError("orthoimage network of " + std::to_string(n) + " inputs and " + std::to_string(h) +
                          " hidden neurons needs " + std::to_string(bytes) + " bytes of uniforms, the driver allows " +
                          std::to_string(max_block));
    }
    glGenBuffers(1, &m_weights);
    glBindBuffer(GL_UNIFORM_BUFFER, m_weights);
    countedBufferData(GL_UNIFORM_BUFFER, bytes, block.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    const GLuint index = glGetUniformBlockIndex(m_network.id(), "OrthoWeights");
    if (index == GL_INVALID_INDEX) throw RenderError("ortho_mlp.frag: uniform block OrthoWeights not found");
    glUniformBlockBinding(m_network.id(), index, 0);
    glGenFramebuffers(1, &m_fbo);
    glGenVertexArrays(1, &m_empty_vao);
}

OrthoGenerator::~OrthoGenerator() {
    if (m_worker.joinable()) {
        {
            std::lock_guard lock(m_mutex);
            m_stop = true;
            m_queue.clear();  // their jobs go with the generator
        }
        m_wake.notify_all();
        m_worker.join();
    }
    const GLuint textures[] = {m_inputs, m_basic};
    glDeleteTextures(2, textures);
    glDeleteFramebuffers(1, &m_fbo);
    glDeleteBuffers(1, &m_weights);
    glDeleteVertexArrays(1, &m_empty_vao);
}

void OrthoGenerator::ensureScratch(int size) {
    if (size <= m_scratch_size) return;
    const GLuint old[] = {m_inputs, m_basic};
    glDeleteTextures(2, old);
    glGenTextures(1, &m_inputs);
    glBindTexture(GL_TEXTURE_2D, m_inputs);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8UI, size, size * kTexels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenTextures(1, &m_basic);
    glBindTexture(GL_TEXTURE_2D, m_basic);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, size, size);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    m_scratch_size = size;
}

GLuint OrthoGenerator::start(const Request& r, std::string& problem) {
    if (!r.tile) {
        problem = "orthoimage requested without a tile";
        return 0;
    }
    problem = mo::orthoLayersProblem(*r.tile);
    if (problem.empty() && (r.size < 1 || r.size > 4096 || !std::has_single_bit(static_cast<unsigned>(r.size)))) {
        problem = "tile " + r.tile->id.toString() + ": orthoimage size " + std::to_string(r.size) +
                  " is not a power of two in 1..4096";
    }
    if (!problem.empty()) return 0;
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexStorage2D(GL_TEXTURE_2D, static_cast<GLsizei>(std::bit_width(static_cast<unsigned>(r.size))), GL_RGB565,
                   r.size, r.size);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    Job job;
    job.request = r;
    job.texture = texture;
    job.field_mask_only = m_field_mask_only;
    job.cancelled = std::make_shared<std::atomic<bool>>(false);
    const OrthoDetail::Options options{r.details, r.vegetation, m_field_mask_only};
    auto made = std::make_shared<std::promise<OrthoDetail::Geometry>>();
    job.detail = made->get_future();
    enqueue(
        [tile = r.tile, options, cancelled = job.cancelled, made] {
            try {
                made->set_value(cancelled->load() ? OrthoDetail::Geometry{} : OrthoDetail::build(*tile, options));
            } catch (...) {
                made->set_exception(std::current_exception());
            }
        },
        false);
    m_jobs.push_back(std::move(job));
    return texture;
}

void OrthoGenerator::queueInputs(Job& job) {
    job.inputs_queued = true;
    auto made = std::make_shared<std::promise<Inputs>>();
    job.inputs_made = made->get_future();
    // Ahead of the queued detail: the network's bands wait for these.
    enqueue(
        [r = job.request, cancelled = job.cancelled, made] {
            try {
                Inputs in;
                if (!cancelled->load()) {
                    const auto t0 = Clock::now();
                    in.planes.resize(planeBytes(r.size) * kTexels);
                    const mo::OrthoTileSampler sampler(*r.tile);  // layers checked in start()
                    std::vector<OrthoInput> rows(static_cast<std::size_t>(r.size) * kEncodeRows);
                    for (int row0 = 0; row0 < r.size; row0 += kEncodeRows) {
                        const int row1 = std::min(r.size, row0 + kEncodeRows);
                        const std::span<OrthoInput> band(
                            rows.data(), static_cast<std::size_t>(r.size) * static_cast<std::size_t>(row1 - row0));
                        sampler.encodeRows(r.offset.x, r.offset.y, r.extent, r.size, row0, row1, band.data());
                        packPlanes(band, r.size, row0, in.planes.data());
                    }
                    in.encode_ms = msSince(t0);
                }
                made->set_value(std::move(in));
            } catch (...) {
                made->set_exception(std::current_exception());
            }
        },
        true);
}

void OrthoGenerator::enqueue(std::function<void()> task, bool first) {
    {
        std::lock_guard lock(m_mutex);
        if (first) {
            m_queue.push_front(std::move(task));
        } else {
            m_queue.push_back(std::move(task));
        }
    }
    if (!m_worker.joinable()) m_worker = std::thread([this] { workerLoop(); });
    m_wake.notify_one();
}

void OrthoGenerator::workerLoop() {
    std::unique_lock lock(m_mutex);
    for (;;) {
        m_wake.wait(lock, [this] { return m_stop || !m_queue.empty(); });
        if (m_stop) return;
        auto task = std::move(m_queue.front());
        m_queue.pop_front();
        lock.unlock();
        task();  // each task hands its result or exception to its job's future
        lock.lock();
    }
}

bool OrthoGenerator::ready(GLuint texture) const {
    return texture != 0 &&
           std::none_of(m_jobs.begin(), m_jobs.end(), [&](const Job& j) { return j.texture == texture; }) &&
           std::find(m_failed.begin(), m_failed.end(), texture) == m_failed.end();
}

void OrthoGenerator::cancel(GLuint texture) {
    std::erase(m_failed, texture);
    // A job in progress may go too: its rows live in the scratch textures, which the next job
    // overwrites from its first row.
    // Its inputs and detail, if the worker has not started them yet, are skipped.
    const auto it = std::find_if(m_jobs.begin(), m_jobs.end(), [&](const Job& j) { return j.texture == texture; });
    if (it == m_jobs.end()) return;
    it->cancelled->store(true);
    m_jobs.erase(it);
}

void OrthoGenerator::uploadPlanes(const std::uint8_t* planes, int size, int row0, int row1) {
    glBindTexture(GL_TEXTURE_2D, m_inputs);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (int k = 0; k < kTexels; ++k) {
        const std::uint8_t* rows = planes + static_cast<std::size_t>(k) * planeBytes(size) +
                                   static_cast<std::size_t>(row0) * static_cast<std::size_t>(size) * 4;
        countedTexSubImage2D(GL_TEXTURE_2D, 0, 0, k * size + row0, size, row1 - row0, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE,
                             rows);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
}

void OrthoGenerator::drawNetwork(int size, int row0, int row1) {
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m_basic, 0);
    const GLenum c0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &c0);
    glViewport(0, 0, size, size);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, row0, size, row1 - row0);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(m_network.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, m_weights);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, m_inputs);
    glUniform1i(m_network.uniform("u_inputs"), 0);
    glUniform1i(m_network.uniform("u_size"), size);
    glBindVertexArray(m_empty_vao);
    countedDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_SCISSOR_TEST);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
}

std::vector<std::uint8_t> OrthoGenerator::runNetwork(std::span<const OrthoInput> inputs, int size) {
    ensureScratch(size);
    std::vector<std::uint8_t> planes(planeBytes(size) * kTexels);
    packPlanes(inputs.first(std::min(inputs.size(), static_cast<std::size_t>(size) * static_cast<std::size_t>(size))),
               size, 0, planes.data());
    uploadPlanes(planes.data(), size, 0, size);
    drawNetwork(size, 0, size);
    std::vector<std::uint8_t> out(static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, out.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return out;
}

std::vector<std::uint8_t> OrthoGenerator::read(GLuint texture, int size) {
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    std::vector<std::uint8_t> out(static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, out.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return out;
}

void OrthoGenerator::step(std::size_t budget) {
    const bool all = budget == 0;
    std::size_t spent = 0;
    while (!m_jobs.empty() && (all || spent < budget)) {
        for (std::size_t i = 0; i < std::min(kInputsAhead, m_jobs.size()); ++i) {
            if (!m_jobs[i].inputs_queued) queueInputs(m_jobs[i]);
        }
        Job& job = m_jobs.front();
        const int size = job.request.size;
        const auto side = static_cast<std::size_t>(size);
        ensureScratch(size);
        if (job.stage == Stage::Bands) {
            if (!job.inputs) {
                if (!all && job.inputs_made.wait_for(std::chrono::seconds(0)) != std::future_status::ready) break;
                try {
                    job.inputs = std::make_shared<const Inputs>(job.inputs_made.get());
                } catch (const std::exception&) {  // out of memory on the worker: the tile keeps its land cover
                    ++m_timings.input_failures;
                    m_failed.push_back(job.texture);
                    m_jobs.pop_front();
                    continue;
                }
                m_timings.encode_ms += job.inputs->encode_ms;
            }
            int rows = size - job.next_row;
            if (!all) {
                const auto affordable = static_cast<int>((budget - spent) / side);
                rows = std::min(rows, std::max(affordable, kBandRows));
            }
            const auto t0 = Clock::now();
            uploadPlanes(job.inputs->planes.data(), size, job.next_row, job.next_row + rows);
            drawNetwork(size, job.next_row, job.next_row + rows);
            m_timings.network_ms += msSince(t0);
            m_timings.pixels += static_cast<std::size_t>(rows) * side;
            job.next_row += rows;
            spent += static_cast<std::size_t>(rows) * side;
            if (job.next_row < size) continue;
            job.inputs.reset();
            job.stage = Stage::CopyAndFields;
            if (!all) break;  // the finish starts in the next call
        }
        if (!all && spent > 0) break;
        if (!job.geometry) {
            if (!all && job.detail.wait_for(std::chrono::seconds(0)) != std::future_status::ready) break;
            // Without the detail (the worker failed: out of memory) the image keeps the basic layer.
            try {
                job.geometry = std::make_shared<const OrthoDetail::Geometry>(job.detail.get());
            } catch (const std::exception&) {
                ++m_timings.detail_failures;
                job.geometry = std::make_shared<const OrthoDetail::Geometry>();
            }
            m_detail.account(*job.geometry);
        }
        const auto t0 = Clock::now();
        const bool done = finishStep(job, all);
        m_timings.finish_ms += msSince(t0);
        if (done) m_jobs.pop_front();
        if (!all) break;  // one step of a finish per call
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void OrthoGenerator::bindImage(const Job& job) {
    const int size = job.request.size;
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, job.texture, 0);
    const GLenum c0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &c0);
    glViewport(0, 0, size, size);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
}

bool OrthoGenerator::finishStep(Job& job, bool all) {
    const Request& r = job.request;
    const int size = r.size;
    bindImage(job);
    glDisable(GL_DITHER);  // RGB565 by rounding alone: the same image on every driver
    OrthoDetail::Target target;
    target.tile = r.tile.get();
    target.offset = r.offset;
    target.extent = r.extent;
    target.size = size;
    target.basic = m_basic;
    target.field_mask_only = job.field_mask_only;
    // The procedural detail (seed 6.7) over the basic layer, reading its colour from it.
    const OrthoDetail::Geometry& geometry = *job.geometry;
    bool done = false;
    do {
        switch (job.stage) {
            case Stage::Bands:  // not reached: step() finishes after the last band
            case Stage::CopyAndFields:
                if (job.field_mask_only) {
                    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
                    glClear(GL_COLOR_BUFFER_BIT);
                } else {
                    glActiveTexture(GL_TEXTURE0);
                    glBindTexture(GL_TEXTURE_2D, m_basic);
                    glUseProgram(m_copy.id());
                    glUniform1i(m_copy.uniform("u_basic"), 0);
                    glBindVertexArray(m_empty_vao);
                    countedDrawArrays(GL_TRIANGLES, 0, 3);
                }
                m_detail.drawFields(target, geometry);
                job.stage = geometry.plant_count > 0 ? Stage::Plants : Stage::Roofs;
                break;
            case Stage::Plants: {
                const std::size_t count = all ? geometry.plant_count : kPlantsPerStep;
                m_detail.drawPlants(target, geometry, job.plants_drawn, count);
                job.plants_drawn = std::min(geometry.plant_count, job.plants_drawn + count);
                if (job.plants_drawn >= geometry.plant_count) job.stage = Stage::Roofs;
                break;
            }
            case Stage::Roofs:
                m_detail.drawRoofs(target, geometry);
                glBindTexture(GL_TEXTURE_2D, job.texture);
                glGenerateMipmap(GL_TEXTURE_2D);
                glBindTexture(GL_TEXTURE_2D, 0);
                ++m_timings.images;
                done = true;
                break;
        }
    } while (all && !done);
    glEnable(GL_DITHER);  // GL's default, which the other passes keep
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return done;
}

}  // namespace navmap::render::gl
