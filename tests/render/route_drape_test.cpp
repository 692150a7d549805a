// SPDX-License-Identifier: Apache-2.0
// The route draped per drawn tile (issue 6): a route with sparse points over a hill stays visible
// along its whole length whether the coarse tile or its four finer children are drawn, and while
// the children are morphed to the coarse level; the driven part is dimmed per draped vertex. The
// route's work is bounded by the tiles drawn: the same route given with many more points draws
// the same pixels, and a route of 20,000 points zig-zagging over the tiles costs what one of 2,000
// does.
// Synthetic tiles, Mesa llvmpipe through EGL.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "gl/gl_renderer.h"
#include "navmap/render/renderer.h"
#include "tile_mesh.h"

namespace {

using namespace navmap::render;
namespace map = navmap::map;

constexpr int kW = 640, kH = 480;
const glm::dvec3 kOrigin{20000.0, -15000.0, 0.0};

double hill(double x, double y) {
    const double dx = x - 500.0, dy = y - 520.0;
    return 900.0 + 260.0 * std::exp(-(dx * dx + dy * dy) / (2.0 * 150.0 * 150.0)) + 12.0 * std::sin(x / 37.0);
}

std::shared_ptr<map::Tile> tileOf(map::TileId id, double x0, double y0, double size, int n) {
    auto t = std::make_shared<map::Tile>();
    t->id = id;
    t->origin_x = kOrigin.x + x0;
    t->origin_y = kOrigin.y + y0;
    t->size_m = size;
    t->dem.size = static_cast<std::uint16_t>(n);
    t->dem.spacing_m = static_cast<float>(size / (n - 1));
    t->dem.coverage = 1.0f;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            t->dem.heights.push_back(static_cast<float>(hill(x0 + c * size / (n - 1), y0 + r * size / (n - 1))));
    return t;
}

// Store-frame route: three points, straight over the hill from west to east.
RouteGeometry route() {
    RouteGeometry r;
    const glm::dvec2 pts[] = {{30.0, 480.0}, {520.0, 530.0}, {970.0, 560.0}};
    double m = 0.0;
    for (std::size_t i = 0; i < std::size(pts); ++i) {
        if (i > 0) m += glm::length(pts[i] - pts[i - 1]);
        r.points.emplace_back(kOrigin.x + pts[i].x, kOrigin.y + pts[i].y, 0.0);
        r.measure_m.push_back(m);
    }
    r.version = 1;
    return r;
}

struct Shot {
    Camera camera;
    Image image;
    glm::ivec3 at(glm::dvec3 store) const {
        const glm::mat4 vp = camera.projection(double(kW) / kH) * camera.viewRelativeTo(kOrigin);
        const glm::vec4 c = vp * glm::vec4(glm::vec3(store - kOrigin), 1.0f);
        const int x = static_cast<int>((c.x / c.w * 0.5f + 0.5f) * kW);
        const int y = static_cast<int>((1.0f - (c.y / c.w * 0.5f + 0.5f)) * kH);
        if (c.w <= 0 || x < 0 || y < 0 || x >= kW || y >= kH) return {-1000, -1000, -1000};
        const auto* px = image.pixel(x, y);
        return {px[0], px[1], px[2]};
    }
};

MapStyle style() {
    MapStyle s = MapStyle::day();
    s.route_width_m = 16.0f;
    return s;
}

Shot renderTiles(const std::vector<std::shared_ptr<const map::Tile>>& tiles, const RouteGeometry& r, double progress,
                 const std::vector<TileMorph>& morph = {}, std::vector<gl::RouteWork>* work = nullptr, int frames = 1) {
    RendererOptions o;
    o.width = kW;
    o.height = kH;
    auto renderer = Renderer::create(o);
    renderer->setMapStyle(style());
    Shot s;
    // Oblique view from the south, steeper than any slope of the hill, so nothing of a route on
    // the surface is hidden, while a straight chord through the hill would be.
    s.camera.eye = kOrigin + glm::dvec3(450.0, -250.0, 2500.0);
    s.camera.target = kOrigin + glm::dvec3(500.0, 520.0, 950.0);
    s.camera.near_m = 10.0;
    s.camera.far_m = 6000.0;
    MapFrame frame;
    frame.camera = s.camera;
    frame.tiles = tiles;
    frame.tile_morph = morph;
    frame.route = &r;
    frame.route_progress_m = progress;
    frame.layers.marker = false;
    // `frames` frames of the same view: the route's work per frame into `work`.
    const auto* gl = dynamic_cast<const gl::GlRenderer*>(renderer.get());
    EXPECT_NE(gl, nullptr) << "not the OpenGL ES renderer";
    for (int i = 0; i < frames; ++i) {
        renderer->renderMap(frame);
        if (work && gl) work->push_back(gl->routeWork());
    }
    s.image = renderer->readSync();
    return s;
}

glm::ivec3 to8(glm::vec3 c) { return glm::ivec3(glm::round(c * 255.0f)); }
bool near(glm::ivec3 a, glm::ivec3 b, int tol) {
    return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol && std::abs(a.z - b.z) <= tol;
}

// Counts route centreline samples that show the route colour (dimmed before `progress`), with
// the surface height of the drawn terrain from `surface`.
struct Coverage {
    int samples = 0, visible = 0;
};
Coverage routeCoverage(const Shot& s, const RouteGeometry& r, double progress,
                       const std::function<double(double, double)>& surface) {
    const glm::ivec3 fill = to8(style().route_color);
    const glm::ivec3 dimmed = to8(glm::mix(style().route_color, glm::vec3(0.6f), 0.65f));
    Coverage c;
    for (std::size_t i = 0; i + 1 < r.points.size(); ++i) {
        const glm::dvec2 a(r.points[i]), b(r.points[i + 1]);
        for (double t = 0.02; t < 0.98; t += 0.02) {
            const glm::dvec2 p = a + t * (b - a);
            const double measure = r.measure_m[i] + t * (r.measure_m[i + 1] - r.measure_m[i]);
            if (std::abs(measure - progress) < 10.0) continue;  // the dimming edge
            ++c.samples;
            const glm::ivec3 px = s.at({p.x, p.y, surface(p.x - kOrigin.x, p.y - kOrigin.y)});
            if (near(px, measure < progress ? dimmed : fill, 24)) {
                ++c.visible;
            } else {
                ADD_FAILURE() << "route sample at " << p.x - kOrigin.x << ", " << p.y - kOrigin.y << " (measure "
                              << measure << " m) shows " << px.x << " " << px.y << " " << px.z;
            }
        }
    }
    return c;
}

struct Tiles {
    std::shared_ptr<const map::Tile> coarse = tileOf({5, 10, 12}, 0.0, 0.0, 1000.0, 9);  // 125 m spacing
    std::vector<std::shared_ptr<const map::Tile>> fine = {
        tileOf({6, 20, 24}, 0.0, 0.0, 500.0, 33), tileOf({6, 21, 24}, 500.0, 0.0, 500.0, 33),
        tileOf({6, 20, 25}, 0.0, 500.0, 500.0, 33), tileOf({6, 21, 25}, 500.0, 500.0, 500.0, 33)};

    double coarseHeight(double x, double y) const { return buildTileMesh(*coarse).grid().heightAt(x, y); }
    double fineHeight(double x, double y) const {
        const int i = (x >= 500.0 ? 1 : 0) + (y >= 500.0 ? 2 : 0);
        return buildTileMesh(*fine[i]).grid().heightAt(x - (i & 1) * 500.0, y - (i >> 1) * 500.0);
    }
};

TEST(RouteDrapeGpu, VisibleAlongTheWholeRouteOnCoarseAndFineTiles) {
    const Tiles t;
    const RouteGeometry r = route();
    const double progress = 0.4 * r.measure_m.back();
    const Shot coarse = renderTiles({t.coarse}, r, progress);
    const Coverage cc = routeCoverage(coarse, r, progress, [&](double x, double y) { return t.coarseHeight(x, y); });
    const Shot fine = renderTiles(t.fine, r, progress);
    const Coverage fc = routeCoverage(fine, r, progress, [&](double x, double y) { return t.fineHeight(x, y); });
    if (cc.visible != cc.samples) (void)writePng("route_drape_coarse.png", coarse.image, nullptr);
    if (fc.visible != fc.samples) (void)writePng("route_drape_fine.png", fine.image, nullptr);
    EXPECT_GT(cc.samples, 80);
    EXPECT_EQ(cc.visible, cc.samples) << "route hidden under the coarse terrain (or not dimmed where driven)";
    EXPECT_EQ(fc.visible, fc.samples) << "route hidden under the fine terrain (or not dimmed where driven)";
}

TEST(RouteDrapeGpu, FollowsTheTerrainWhileFineTilesAreMorphedToTheCoarseLevel) {
    const Tiles t;
    const RouteGeometry r = route();
    // Every vertex beyond the range end: the fine tiles show the coarse tile's surface.
    std::vector<TileMorph> morph(4);
    for (auto& m : morph) {
        m.ancestors[0] = t.coarse;
        m.start_m[0] = 1.0f;  // only the first slot: the coarse tile has no ancestors here
        m.end_m[0] = 2.0f;
    }
    const Shot s = renderTiles(t.fine, r, 0.0, morph);
    const Coverage c = routeCoverage(s, r, 0.0, [&](double x, double y) { return t.coarseHeight(x, y); });
    if (c.visible != c.samples) (void)writePng("route_drape_morphed.png", s.image, nullptr);
    EXPECT_GT(c.samples, 80);
    EXPECT_EQ(c.visible, c.samples) << "route does not follow the morphed terrain";
    // And the terrain really is the coarse one: the morphed image matches the coarse tile's.
    const Shot coarse = renderTiles({t.coarse}, r, 0.0);
    double diff = 0.0;
    for (std::size_t i = 0; i < s.image.rgba.size(); i += 4)
        for (int k = 0; k < 3; ++k) diff += std::abs(int(s.image.rgba[i + k]) - int(coarse.image.rgba[i + k]));
    diff /= 3.0 * (s.image.rgba.size() / 4);
    EXPECT_LT(diff, 1.0) << "fully morphed fine tiles differ from their parent by " << diff << " per channel";
}

// `r` given again with a point every `step_m` on it: the same line, many more points.
RouteGeometry densified(const RouteGeometry& r, double step_m) {
    RouteGeometry d;
    for (std::size_t i = 0; i + 1 < r.points.size(); ++i) {
        const auto steps = static_cast<int>(glm::length(r.points[i + 1] - r.points[i]) / step_m);
        for (int k = 0; k < steps; ++k) {
            const double t = double(k) / steps;
            d.points.push_back(glm::mix(r.points[i], r.points[i + 1], t));
            d.measure_m.push_back(r.measure_m[i] + t * (r.measure_m[i + 1] - r.measure_m[i]));
        }
    }
    d.points.push_back(r.points.back());
    d.measure_m.push_back(r.measure_m.back());
    d.version = 1;
    return d;
}

// Pixels (of kW x kH) whose colour differs by more than `tol` in a channel.
int differingPixels(const Image& a, const Image& b, int tol) {
    int n = 0;
    for (std::size_t i = 0; i + 3 < a.rgba.size() && i + 3 < b.rgba.size(); i += 4) {
        for (int k = 0; k < 3; ++k) {
            if (std::abs(int(a.rgba[i + k]) - int(b.rgba[i + k])) > tol) {
                ++n;
                break;
            }
        }
    }
    return n;
}

TEST(RouteDrapeGpu, TheSameRouteGivenWithManyMorePointsDrawsTheSamePixels) {
    const Tiles t;
    const RouteGeometry r = route();
    const RouteGeometry dense = densified(r, 0.1);  // about 9,500 points
    ASSERT_GT(dense.points.size(), 9000u);
    const double progress = 0.4 * r.measure_m.back();
    std::vector<gl::RouteWork> sparse_work, dense_work;
    const Shot sparse = renderTiles(t.fine, r, progress, {}, &sparse_work);
    const Shot many = renderTiles(t.fine, dense, progress, {}, &dense_work);
    const int differing = differingPixels(sparse.image, many.image, 8);
    if (differing > 0) (void)writePng("route_drape_dense.png", many.image, nullptr);
    EXPECT_EQ(differing, 0) << "the simplified dense route draws other pixels";
    ASSERT_EQ(dense_work.size(), 1u);
    ASSERT_EQ(sparse_work.size(), 1u);
    EXPECT_EQ(dense_work[0].tiles_draped, 4u) << "a normal route is draped whole in one frame";
    EXPECT_EQ(dense_work[0].pieces, sparse_work[0].pieces) << "simplified to the same segments";
    EXPECT_EQ(dense_work[0].segments_draped, sparse_work[0].segments_draped);
    const Coverage c = routeCoverage(many, r, progress, [&](double x, double y) { return t.fineHeight(x, y); });
    EXPECT_EQ(c.visible, c.samples);
}

// `points` points zig-zagging east-west over the four fine tiles (beyond their west and east
// edges), from their south edge to their north one.
RouteGeometry zigZag(int points) {
    RouteGeometry r;
    double m = 0.0;
    for (int i = 0; i < points; ++i) {
        const glm::dvec2 p(i % 2 == 0 ? -100.0 : 1100.0, 1000.0 * i / (points - 1));
        if (i > 0) m += glm::length(p - (glm::dvec2(r.points.back()) - glm::dvec2(kOrigin)));
        r.points.emplace_back(kOrigin.x + p.x, kOrigin.y + p.y, 0.0);
        r.measure_m.push_back(m);
    }
    r.version = 1;
    return r;
}

// Pixels showing the route's fill colour (either shade of it).
int routePixels(const Image& image) {
    const glm::ivec3 fill = to8(style().route_color);
    const glm::ivec3 dimmed = to8(glm::mix(style().route_color, glm::vec3(0.6f), 0.65f));
    int n = 0;
    for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4) {
        const glm::ivec3 px(image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]);
        if (near(px, fill, 24) || near(px, dimmed, 24)) ++n;
    }
    return n;
}

TEST(RouteDrapeGpu, AZigZagRouteOfTwentyThousandPointsCostsWhatOneOfTwoThousandDoes) {
    const Tiles t;
    std::vector<gl::RouteWork> w2k, w20k;
    const RouteGeometry z2k = zigZag(2000), z20k = zigZag(20000);
    const Shot a = renderTiles(t.fine, z2k, 0.0, {}, &w2k, 3);
    const Shot b = renderTiles(t.fine, z20k, 0.0, {}, &w20k, 3);
    // Summed over the frames (the tiles are draped once), the pieces of the last frame.
    auto total = [](const std::vector<gl::RouteWork>& w) {
        gl::RouteWork sum = w.back();
        sum.tiles_draped = sum.segments_draped = sum.segments_left_out = sum.segments_clipped = 0;
        for (const gl::RouteWork& f : w) {
            sum.tiles_draped += f.tiles_draped;
            sum.segments_clipped += f.segments_clipped;
            sum.segments_draped += f.segments_draped;
            sum.segments_left_out += f.segments_left_out;
        }
        return sum;
    };
    const gl::RouteWork s2k = total(w2k), s20k = total(w20k);
    // Unbounded, every segment is draped on each tile it crosses (about 50 pieces per tile):
    // 200,000 and 2,000,000 pieces, all uploaded. Bounded by the tiles instead.
    EXPECT_EQ(w2k[0].tiles_draped, 4u);
    EXPECT_EQ(s2k.tiles_draped, 4u);
    EXPECT_EQ(s20k.tiles_draped, 4u) << "each tile draped once";
    // The first frame drapes no more than kRouteSegmentsPerFrame (and the nearest tile).
    EXPECT_GE(w20k[0].tiles_deferred, 1u);
    EXPECT_LE(w20k[0].segments_clipped, gl::kRouteSegmentsPerFrame + 20000u);
    EXPECT_EQ(w20k.back().tiles_deferred, 0u);
    EXPECT_LE(s2k.pieces, 4 * kRoutePiecesPerTile);
    EXPECT_LE(s20k.pieces, 4 * kRoutePiecesPerTile);
    for (const gl::RouteWork& f : w20k) EXPECT_LE(f.pieces_uploaded, 4 * kRoutePiecesPerTile);
    EXPECT_LT(s20k.pieces, s2k.pieces * 3 / 2) << s2k.pieces << " " << s20k.pieces;
    EXPECT_LT(s20k.segments_draped, s2k.segments_draped * 3 / 2);
    // Each segment crosses two of the tiles: 40,000 clipped, nearly all of them left out.
    EXPECT_GT(s20k.segments_left_out, 38000u) << "most segments lie where the route is drawn already";
    // And both still cover the tiles with the route.
    const int pa = routePixels(a.image), pb = routePixels(b.image);
    if (pa < kW * kH / 10 || pb < kW * kH / 10) {
        (void)writePng("route_zigzag_2000.png", a.image, nullptr);
        (void)writePng("route_zigzag_20000.png", b.image, nullptr);
    }
    EXPECT_GT(pa, kW * kH / 10);
    EXPECT_GT(pb, kW * kH / 10);
}

}  // namespace
