// SPDX-License-Identifier: Apache-2.0
#include "sv_roads.h"
#include "road_uniforms.h"
#include "vertex_layout.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "gpu_tile.h"
#include "road_draping.h"
#include "tile_mesh.h"

namespace navmap::render::gl {

namespace {

// SvRoadInstance, repeated per box corner.
void setupBoxAttributes() {
    setVertexAttributes(sizeof(SvRoadInstance), {{0, 4, GL_FLOAT, offsetof(SvRoadInstance, segment)},
                                                 {1, 2, GL_FLOAT, offsetof(SvRoadInstance, z_range)},
                                                 {2, 1, GL_FLOAT, offsetof(SvRoadInstance, road_class)},
                                                 {3, 1, GL_FLOAT, offsetof(SvRoadInstance, reach)},
                                                 {4, 3, GL_FLOAT, offsetof(SvRoadInstance, plane)}});
}

// The twelve triangles of a box; corners as in roads_sv.vert, counter-clockwise seen from outside,
// so GL_FRONT culling keeps the far faces.
constexpr std::uint32_t kBoxIndices[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 4, 6, 0, 6, 2,
                                           1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3};

// What is attached at `attachment` of the bound framebuffer.
void attachmentOf(GLenum attachment, GLint& type, GLint& name) {
    glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    name = 0;
    if (type != GL_NONE) {
        glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    }
}

void attach(GLenum attachment, GLint type, GLint name) {
    if (type == GL_RENDERBUFFER) {
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, static_cast<GLuint>(name));
    } else if (type == GL_TEXTURE) {
        glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, static_cast<GLuint>(name), 0);
    }
}

// An incomplete framebuffer (a driver without multisampled R32F, say) is an expected failure at
// run time: reported on stderr, and the frame falls back to geometric roads.
bool complete(const char* what) {
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status == GL_FRAMEBUFFER_COMPLETE) return true;
    std::fprintf(stderr,
                 "navmap: shadow-volume roads: framebuffer (%s) incomplete: status 0x%04x; drawing geometric roads\n",
                 what, status);
    return false;
}

}  // namespace

namespace {

// A tile's DEM as a HeightGrid (flat 2x2 at 0 m without one, as the terrain mesh renders it).
struct SurfaceGrid {
    std::vector<float> flat;
    HeightGrid grid;
    glm::dvec2 offset{0.0};  // tile-local position of the grid's (0, 0)

    SurfaceGrid(const map::Tile& t, glm::dvec2 tile_origin) {
        const auto& dem = t.dem;
        if (dem.size >= 2 && dem.heights.size() == std::size_t{dem.size} * dem.size) {
            grid = HeightGrid{dem.size, t.size_m / (dem.size - 1), dem.heights.data()};
        } else {
            flat.assign(4, 0.0f);
            grid = HeightGrid{2, t.size_m, flat.data()};
        }
        offset = glm::dvec2(t.origin_x, t.origin_y) - tile_origin;
    }
    SurfaceGrid(const SurfaceGrid&) = delete;
};

// Slope bound of a grid: the steepest sample difference; a triangle's gradient is at most
// sqrt(2) of it.
float maxSlope(const HeightGrid& g) {
    float max_step = 0.0f;
    for (int r = 0; r < g.size; ++r) {
        for (int c = 0; c < g.size; ++c) {
            if (c + 1 < g.size) max_step = std::max(max_step, std::abs(g.at(r, c + 1) - g.at(r, c)));
            if (r + 1 < g.size) max_step = std::max(max_step, std::abs(g.at(r + 1, c) - g.at(r, c)));
        }
    }
    return static_cast<float>(1.5 * max_step / g.spacing);
}

// A plane z = h0 + g . (x - p0) in tile-local metres.
struct Plane {
    glm::dvec2 p0{0.0};
    double h0 = 0.0;
    glm::dvec2 g{0.0};
    [[nodiscard]] double at(glm::dvec2 x) const { return h0 + glm::dot(g, x - p0); }
};

// Exact range of the triangulated surface's height above `plane` over a convex polygon
// (tile-local): surface minus plane is linear on each triangle, so its extremes lie at polygon
// corners, at crossings of the polygon edges with triangle edges (drapePolyline inserts exactly
// those) or at grid vertices inside. Where the polygon leaves the grid, the terrain beyond is
// bounded by the slopes.
void surfaceRange(const SurfaceGrid& s, std::span<const glm::dvec2> polygon, const Plane& plane, float slope,
                  float& zmin, float& zmax) {
    const HeightGrid& g = s.grid;
    auto above = [&](glm::dvec2 grid_xy, double z) { return static_cast<float>(z - plane.at(grid_xy + s.offset)); };
    std::vector<glm::dvec2> ring;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& p : polygon) {
        ring.push_back(p - s.offset);
        lo = glm::min(lo, ring.back());
        hi = glm::max(hi, ring.back());
    }
    ring.push_back(ring.front());
    for (const auto& p : drapePolyline(g, ring)) {
        const float z = above(glm::dvec2(p), p.z);
        zmin = std::min(zmin, z);
        zmax = std::max(zmax, z);
    }
    const int c0 = std::clamp(static_cast<int>(std::ceil(lo.x / g.spacing)), 0, g.size - 1);
    const int c1 = std::clamp(static_cast<int>(std::floor(hi.x / g.spacing)), 0, g.size - 1);
    const int r0 = std::clamp(static_cast<int>(std::ceil(lo.y / g.spacing)), 0, g.size - 1);
    const int r1 = std::clamp(static_cast<int>(std::floor(hi.y / g.spacing)), 0, g.size - 1);
    for (int r = r0; r <= r1; ++r) {
        for (int c = c0; c <= c1; ++c) {
            const glm::dvec2 v(c * g.spacing, r * g.spacing);
            bool inside = true;  // counter-clockwise convex polygon: left of every edge
            for (std::size_t i = 0; i + 1 < ring.size() && inside; ++i) {
                const glm::dvec2 e = ring[i + 1] - ring[i], d = v - ring[i];
                inside = e.x * d.y - e.y * d.x >= -1e-9;
            }
            if (inside) {
                const float z = above(v, g.at(r, c));
                zmin = std::min(zmin, z);
                zmax = std::max(zmax, z);
            }
        }
    }
    const double extent = g.extent();
    const double outside = std::max({0.0, -lo.x, -lo.y, hi.x - extent, hi.y - extent});
    const auto grow = static_cast<float>(outside * (slope + glm::length(plane.g)));
    zmin -= grow;
    zmax += grow;
}

}  // namespace

SvTileRoads buildSvTileRoads(const map::Tile& tile, const RoadStyle& style,
                             std::span<const map::Tile* const> ancestors) {
    SvTileRoads out;
    const glm::dvec2 origin(tile.origin_x, tile.origin_y);
    std::vector<std::unique_ptr<SurfaceGrid>> surfaces;
    surfaces.push_back(std::make_unique<SurfaceGrid>(tile, origin));
    for (const map::Tile* a : ancestors) {
        if (a) surfaces.push_back(std::make_unique<SurfaceGrid>(*a, origin));
    }
    for (const auto& g : surfaces) out.max_slope = std::max(out.max_slope, maxSlope(g->grid));

    // The volume of a piece: a plane through the terrain under it (along the centreline, tilted by
    // the cross slope at its middle) and the range of the terrain's height above that plane under
    // the piece's box (its capped footprint widened to reach_m), on the tile's own surface and its
    // ancestors', which the terrain geomorphs to in the distance. Following the terrain's slope
    // this way keeps the boxes thin on hillsides, where a flat height range would be tall.
    auto volume = [&](SvRoadInstance& inst, glm::dvec2 a, glm::dvec2 b, double reach_m) {
        const glm::dvec2 d = b - a;
        const double len = glm::length(d);
        const glm::dvec2 t = len > 1e-9 ? d / len : glm::dvec2(1.0, 0.0);
        const glm::dvec2 n(-t.y, t.x);
        const double r = reach_m;
        const HeightGrid& own = surfaces.front()->grid;
        const glm::dvec2 mid = 0.5 * (a + b);
        Plane plane;
        plane.p0 = a;
        plane.h0 = own.heightAt(a.x, a.y);
        const double along = len > 1e-9 ? (own.heightAt(b.x, b.y) - plane.h0) / len : 0.0;
        const glm::dvec2 l = mid + r * n, rr = mid - r * n;
        const double across = (own.heightAt(l.x, l.y) - own.heightAt(rr.x, rr.y)) / (2.0 * r);
        plane.g = along * t + across * n;
        const glm::dvec2 box[4] = {a - r * t - r * n, b + r * t - r * n, b + r * t + r * n, a - r * t + r * n};
        float zmin = std::numeric_limits<float>::max(), zmax = std::numeric_limits<float>::lowest();
        for (const auto& g : surfaces) surfaceRange(*g, box, plane, out.max_slope, zmin, zmax);
        inst.plane = glm::vec3(static_cast<float>(plane.h0), glm::vec2(plane.g));
        inst.z_range = glm::vec2(zmin - 0.5f, zmax + 0.5f);  // float rounding of the rendered surface
    };

    struct Piece {
        SvRoadInstance inst;
        int order;
    };
    std::vector<Piece> pieces;
    for (const auto& road : tile.roads) {
        if (road.points.size() < 2) continue;
        if (road.flags & map::road_flags::kTunnel) continue;  // hidden in the map view, as for GEO
        const int order = roadDrawOrder(road);
        const float reach = 0.5f * style.of(static_cast<int>(road.cls)).outerWidth() + 1.0f;
        for (std::size_t i = 0; i + 1 < road.points.size(); ++i) {
            const glm::dvec2 a(road.points[i].x, road.points[i].y), b(road.points[i + 1].x, road.points[i + 1].y);
            // Long segments are cut into pieces of at most kPieceM, each with its own (tighter)
            // height range: less fill for the boxes, the costly part on a software rasterizer.
            const int count = std::max(1, static_cast<int>(std::ceil(glm::length(b - a) / SvRoads::kPieceM)));
            for (int k = 0; k < count; ++k) {
                const glm::dvec2 p = glm::mix(a, b, double(k) / count), q = glm::mix(a, b, double(k + 1) / count);
                SvRoadInstance inst;
                inst.segment = glm::vec4(glm::vec2(p), glm::vec2(q));
                volume(inst, p, q, reach);
                inst.road_class = static_cast<float>(road.cls);
                inst.flags = static_cast<float>(road.flags);
                inst.reach = reach;
                pieces.push_back({inst, order});
            }
        }
    }
    std::stable_sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) { return a.order < b.order; });
    out.instances.reserve(pieces.size());
    for (const auto& p : pieces) out.instances.push_back(p.inst);
    out.class_first.fill(out.instances.size());
    out.bridge_first = out.instances.size();
    for (std::size_t i = out.instances.size(); i-- > 0;) {
        const SvRoadInstance& r = out.instances[i];
        if (static_cast<int>(r.flags) & map::road_flags::kBridge) {
            out.bridge_first = i;
            continue;
        }
        const int c = std::clamp(static_cast<int>(r.road_class), 0, kStyledRoadClasses - 1);
        out.class_first[static_cast<std::size_t>(c)] = i;
    }
    return out;
}

RoadTechnique resolveRoadTechnique(const MapFrame& frame) {
    const RoadTechnique t = frame.layers.road_technique;
    if (t != RoadTechnique::Auto) return t;
    for (const auto& tile : frame.tiles) {
        if (tile && tile->dem.size >= 2 && tile->dem.spacing_m > 0.0f &&
            tile->dem.spacing_m < kShadowVolumeAutoSpacingM) {
            return RoadTechnique::ShadowVolume;
        }
    }
    return RoadTechnique::Geometric;
}

struct SvRoads::GpuTileRoads {
    const map::Tile* source = nullptr;  // identity of the tile object the buffers were made from
    std::weak_ptr<const map::Tile> source_ref;
    std::vector<const map::Tile*> ancestors;  // geomorph targets whose surfaces the z ranges include
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
    std::array<GLsizei, kStyledRoadClasses> class_first{};
    GLsizei bridge_first = 0;
    float max_slope = 0.0f;
    std::uint64_t last_used = 0;

    ~GpuTileRoads() {
        glDeleteVertexArrays(1, &vao);
        glDeleteBuffers(1, &vbo);
    }
};

SvRoads* SvRoads::forFrame(std::unique_ptr<SvRoads>& slot, const MapFrame& frame, const RenderTarget& target,
                           const GlFeatures& features) {
    if (!frame.layers.roads || !frame.layers.terrain) return nullptr;  // SV drapes onto the terrain
    if (resolveRoadTechnique(frame) != RoadTechnique::ShadowVolume) return nullptr;
    if (!slot) slot = std::make_unique<SvRoads>(features.colorBufferFloat());
    if (!slot->m_supported) return nullptr;
    return slot->setupTarget(target) ? slot.get() : nullptr;
}

SvRoads::SvRoads(bool color_buffer_float) : m_box_indices(kBoxIndices, 8) {
    // The terrain depth is an R32F colour target: core in ES 3.2, EXT_color_buffer_float before.
    // Without it the roads stay geometric (said once per renderer, and in DeviceInfo::features_off).
    m_supported = color_buffer_float;
    if (!m_supported) {
        std::fprintf(stderr, "navmap: shadow-volume roads need GL_EXT_color_buffer_float; drawing geometric roads\n");
        return;
    }
    m_program = ShaderProgram::fromEmbedded("roads_sv.vert", "roads_sv.frag");
}

SvRoads::~SvRoads() {
    m_tiles.clear();
    const GLuint fbos[] = {m_fbo, m_resolve_fbo};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(1, &m_depth_rb);
    glDeleteTextures(1, &m_depth_texture);
}

bool SvRoads::setupTarget(const RenderTarget& target) {
    // The target's own attachments, so the terrain pass draws colour and depth as usual.
    target.bindForDrawing(false);
    Key key;
    attachmentOf(GL_COLOR_ATTACHMENT0, key.color_type, key.color);
    attachmentOf(GL_DEPTH_ATTACHMENT, key.depth_type, key.depth);
    key.width = target.width();
    key.height = target.height();
    key.samples = target.samples();
    if (key == m_key) return m_usable;
    m_key = key;
    m_usable = false;

    const GLuint fbos[] = {m_fbo, m_resolve_fbo};
    glDeleteFramebuffers(2, fbos);
    m_fbo = m_resolve_fbo = 0;

    // One terrain depth buffer for every target (scratch within a frame, ScratchSize): kept while
    // it covers the target; roads_sv.frag reads it with texelFetch at the pixel. Only the
    // framebuffer is re-made when the displays take turns, not the buffer.
    if (key.samples != m_depth_samples) {
        m_depth_size = {};
        m_depth_samples = key.samples;
    }
    if (m_depth_size.grow(key.width, key.height)) {
        glDeleteRenderbuffers(1, &m_depth_rb);
        glDeleteTextures(1, &m_depth_texture);
        m_depth_rb = m_depth_texture = 0;
        glGenTextures(1, &m_depth_texture);
        glBindTexture(GL_TEXTURE_2D, m_depth_texture);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, m_depth_size.width, m_depth_size.height);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // float: not filterable; texelFetch anyway
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glBindTexture(GL_TEXTURE_2D, 0);
        if (key.samples > 0) {
            // Multisampled target: draw the depth multisampled, resolve into the texture afterwards.
            glGenRenderbuffers(1, &m_depth_rb);
            glBindRenderbuffer(GL_RENDERBUFFER, m_depth_rb);
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, key.samples, GL_R32F, m_depth_size.width,
                                             m_depth_size.height);
            glBindRenderbuffer(GL_RENDERBUFFER, 0);
        }
    }

    glGenFramebuffers(1, &m_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    attach(GL_COLOR_ATTACHMENT0, key.color_type, key.color);
    if (key.samples > 0) {
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT3, GL_RENDERBUFFER, m_depth_rb);
    } else {
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT3, GL_TEXTURE_2D, m_depth_texture, 0);
    }
    attach(GL_DEPTH_STENCIL_ATTACHMENT, key.depth_type, key.depth);
    if (!complete("terrain depth")) return false;
    if (key.samples > 0) {
        glGenFramebuffers(1, &m_resolve_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, m_resolve_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m_depth_texture, 0);
        if (!complete("terrain depth resolve")) return false;
    }
    m_usable = true;
    return true;
}

void SvRoads::beginTerrain(const RenderTarget& target) {
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_NONE, GL_NONE, GL_COLOR_ATTACHMENT3};
    glDrawBuffers(4, buffers);
    glViewport(0, 0, target.width(), target.height());
    const GLfloat none[] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 3, none);
}

void SvRoads::endTerrain(const RenderTarget& target) {
    if (m_resolve_fbo) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo);
        glReadBuffer(GL_COLOR_ATTACHMENT3);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_resolve_fbo);
        glBlitFramebuffer(0, 0, target.width(), target.height(), 0, 0, target.width(), target.height(),
                          GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
    }
    target.bindForDrawing(false);
}

SvRoads::GpuTileRoads* SvRoads::tileRoads(const std::shared_ptr<const map::Tile>& tile,
                                          const std::vector<const map::Tile*>& ancestors, const RoadStyle& style) {
    auto it = m_tiles.find(tile->id.key());
    // Rebuilt when a geomorph ancestor appears that the height ranges do not include yet.
    auto covered = [&](const GpuTileRoads& g) {
        for (const map::Tile* a : ancestors) {
            if (std::find(g.ancestors.begin(), g.ancestors.end(), a) == g.ancestors.end()) return false;
        }
        return true;
    };
    if (it != m_tiles.end() && sameTileObject(it->second->source, it->second->source_ref, tile.get()) &&
        covered(*it->second))
        return it->second.get();
    const SvTileRoads cpu = buildSvTileRoads(*tile, style, ancestors);
    auto gpu = std::make_unique<GpuTileRoads>();
    gpu->source = tile.get();
    gpu->source_ref = tile;
    gpu->ancestors = ancestors;
    gpu->count = static_cast<GLsizei>(cpu.instances.size());
    for (std::size_t c = 0; c < cpu.class_first.size(); ++c)
        gpu->class_first[c] = static_cast<GLsizei>(cpu.class_first[c]);
    gpu->bridge_first = static_cast<GLsizei>(cpu.bridge_first);
    gpu->max_slope = cpu.max_slope;
    if (gpu->count > 0) {
        glGenVertexArrays(1, &gpu->vao);
        glGenBuffers(1, &gpu->vbo);
        glBindVertexArray(gpu->vao);
        glBindBuffer(GL_ARRAY_BUFFER, gpu->vbo);
        // Each box repeated for its eight corners and drawn indexed, not instanced: llvmpipe runs an
        // instanced draw as one small draw per instance (see the geometric road quads).
        std::vector<SvRoadInstance> corners;
        corners.reserve(cpu.instances.size() * 8);
        for (const auto& b : cpu.instances) corners.insert(corners.end(), 8, b);
        countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(corners.size() * sizeof(SvRoadInstance)),
                          corners.data(), GL_STATIC_DRAW);
        setupBoxAttributes();
        m_box_indices.bind(cpu.instances.size());
        glBindVertexArray(0);
    }
    GpuTileRoads* raw = gpu.get();
    m_tiles[tile->id.key()] = std::move(gpu);
    return raw;
}

std::size_t SvRoads::draw(const MapFrame& frame, const glm::mat4& projection, const RenderTarget& target,
                          const RoadStyle& style) {
    ++m_frame;
    std::vector<std::pair<GpuTileRoads*, glm::dvec3>> tiles;
    tiles.reserve(frame.tiles.size());
    std::vector<const map::Tile*> ancestors;
    for (std::size_t i = 0; i < frame.tiles.size(); ++i) {
        const auto& tile = frame.tiles[i];
        if (!tile) continue;
        ancestors.clear();
        if (i < frame.tile_morph.size()) {
            for (const auto& a : frame.tile_morph[i].ancestors) {
                if (a) ancestors.push_back(a.get());
            }
        }
        GpuTileRoads* g = tileRoads(tile, ancestors, style);
        g->last_used = m_frame;
        if (g->count > 0) tiles.emplace_back(g, glm::dvec3(tile->origin_x, tile->origin_y, 0.0));
    }

    target.bindForDrawing(true);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glDisable(GL_BLEND);
    // seed 3.5.2: front-face culling; the fragment stage computes the entry point itself.
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);

    ShaderProgram& p = m_program;
    glUseProgram(p.id());
    setRoadClassUniforms(p, style,
                         selectionFades(style, projection[1][1] * 0.5f * static_cast<float>(target.height()),
                                        frame.layers.road_selection));  // seed 7.3
    glUniform3f(p.uniform("u_scale"), style.scale_threshold_m, style.max_scale, 0.0f);
    glUniformMatrix4fv(p.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(projection));
    const glm::dvec3 forward = glm::normalize(frame.camera.target - frame.camera.eye);
    glUniform3fv(p.uniform("u_forward"), 1, glm::value_ptr(glm::vec3(forward)));
    // Window depth of view depth z: 0.5 * (-P22 + P32 / z) + 0.5. The pull of 0.4 % keeps the
    // road above the 24-bit rounding of the terrain's depth at any distance up to the far plane.
    glUniform3f(p.uniform("u_depth"), projection[2][2], projection[3][2], 0.004f);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, m_depth_texture);
    glUniform1i(p.uniform("u_terrain_depth"), 0);

    std::size_t segments = 0;
    for (int pass = 0; pass < 2; ++pass) {
        glUniform1i(p.uniform("u_pass"), pass);
        for (const auto& [g, origin] : tiles) {
            glUniformMatrix4fv(p.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(frame.camera.viewRelativeTo(origin)));
            glUniform3fv(p.uniform("u_eye"), 1, glm::value_ptr(glm::vec3(frame.camera.eye - origin)));
            glUniform1f(p.uniform("u_max_slope"), g->max_slope);
            glBindVertexArray(g->vao);
            if (pass == 0) {
                // Casing: only from the first class that has one (bridges always), as for GEO.
                GLsizei first = g->bridge_first;
                for (int c = 0; c < kStyledRoadClasses; ++c) {
                    if (style.classes[c].casing_m > 0.0f) first = std::min(first, g->class_first[c]);
                }
                if (first >= g->count) continue;
                m_box_indices.draw(first, g->count - first);
            } else {
                m_box_indices.draw(0, g->count);
                segments += static_cast<std::size_t>(g->count);
            }
        }
    }
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glCullFace(GL_BACK);
    glDisable(GL_CULL_FACE);

    // Keep the buffers of recently drawn tiles (the view moves back and forth), drop the rest.
    constexpr std::uint64_t kKeepFrames = 300;
    for (auto it = m_tiles.begin(); it != m_tiles.end();) {
        if (m_frame - it->second->last_used > kKeepFrames)
            it = m_tiles.erase(it);
        else
            ++it;
    }
    return segments;
}

}  // namespace navmap::render::gl
