// SPDX-License-Identifier: Apache-2.0
// GL text layer on Mesa llvmpipe: real pixels of fill, outline and halo (seed 4.5.2, Fig. 4.7),
// rotation, alpha, world-space labels hidden by depth, and a golden image of a few labels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/egl_context.h"
#include "gl/readback.h"
#include "gl/render_target.h"
#include "gl/text_layer.h"
#include "golden.h"
#include "navmap/render/text/text_engine.h"
#include "text/label_text_style.h"

namespace {

using namespace navmap::render;
using namespace navmap::render::text;

constexpr float kGrey = 0.5f;  // background, 128

struct Box {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
    [[nodiscard]] bool empty() const { return x1 < x0; }
    [[nodiscard]] int w() const { return x1 - x0 + 1; }
    [[nodiscard]] int h() const { return y1 - y0 + 1; }
};

class TextLayerTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (debianFontFiles().regular.size() < 2) {
            GTEST_SKIP() << "needs fonts-dejavu-core and fonts-droid-fallback";
        }
        try {
            m_context = std::make_unique<gl::EglContext>(Platform::Auto);
        } catch (const RenderError& e) {
            GTEST_SKIP() << "no EGL/GLES 3 context: " << e.what();
        }
        m_engine = std::make_unique<TextEngine>();
        m_layer = std::make_unique<gl::TextLayer>(m_engine->atlas());
    }

    void begin(int w, int h, glm::vec3 bg = glm::vec3(kGrey)) {
        m_target = std::make_unique<gl::RenderTarget>(w, h, 1);
        m_target->clear(bg.r, bg.g, bg.b);
        m_target->bindForDrawing(false);
        m_engine->beginFrame();
    }

    Image finish() {
        m_target->resolve();
        return gl::readPixelsSync(m_target->width(), m_target->height());
    }

    static glm::ivec3 px(const Image& img, int x, int y) {
        const auto* p = img.pixel(x, y);
        return {p[0], p[1], p[2]};
    }

    // Bounding box of pixels that differ from the background by more than `tol`.
    static Box inkBox(const Image& img, glm::ivec3 bg, int tol = 24, int x_from = 0, int x_to = -1) {
        Box b;
        if (x_to < 0) x_to = img.width;
        for (int y = 0; y < img.height; ++y)
            for (int x = x_from; x < x_to; ++x) {
                const glm::ivec3 d = glm::abs(px(img, x, y) - bg);
                if (std::max({d.x, d.y, d.z}) > tol) {
                    b.x0 = std::min(b.x0, x);
                    b.y0 = std::min(b.y0, y);
                    b.x1 = std::max(b.x1, x);
                    b.y1 = std::max(b.y1, y);
                }
            }
        return b;
    }

    std::unique_ptr<gl::EglContext> m_context;
    std::unique_ptr<TextEngine> m_engine;
    std::unique_ptr<gl::TextLayer> m_layer;
    std::unique_ptr<gl::RenderTarget> m_target;
};

TextStyle bandsStyle() {
    TextStyle s;
    s.fill = glm::vec4(1.0f, 0.85f, 0.0f, 1.0f);      // yellow
    s.outline = glm::vec4(0.05f, 0.05f, 0.1f, 1.0f);  // dark
    s.outline_px = 3.0f;
    s.halo = glm::vec4(1.0f, 1.0f, 1.0f, 1.0f);  // white
    s.halo_px = 8.0f;
    return s;
}

TEST_F(TextLayerTest, FillOutlineAndHaloBands) {
    begin(256, 160);
    const LaidOutText l = m_engine->layout(m_engine->run("I"), 96.0f);
    TextDraw d;
    d.quads = l.quads;
    d.size_px = l.size_px;
    d.position = {128.0f, 80.0f};
    d.style = bandsStyle();
    m_layer->drawScreen(std::span(&d, 1), {256, 160});
    const Image img = finish();
    EXPECT_EQ(m_layer->stats().glyphs, 1u);

    // Walk left along the row through the anchor from inside the stem.
    const int y = 80;
    auto is_fill = [&](int x) {
        const glm::ivec3 c = px(img, x, y);
        return c.r > 230 && c.g > 195 && c.b < 40;
    };
    int start = 128;
    while (start > 0 && !is_fill(start)) --start;  // the stem's ink may sit off the anchor
    ASSERT_TRUE(is_fill(start)) << "no fill colour on row " << y;
    int edge = start;
    while (edge > 0 && is_fill(edge - 1)) --edge;  // first fill pixel from the left
    const int stem_w = [&] {
        int x = edge;
        while (is_fill(x)) ++x;
        return x - edge;
    }();
    EXPECT_GE(stem_w, 7) << "DejaVu I at 96 px: stem about 9.4 px, antialiased edges excluded";
    // Dark outline ring right outside the fill (3 px).
    const glm::ivec3 ring = px(img, edge - 2, y);
    EXPECT_LT(std::max({ring.r, ring.g, ring.b}), 60) << "outline at x=" << edge - 2;
    // Halo: lighter than the background just outside the outline (opaque for half its width).
    const glm::ivec3 halo = px(img, edge - 3 - 3, y);
    EXPECT_GT(std::min({halo.r, halo.g, halo.b}), 235) << "halo at x=" << edge - 6;
    // Background further away, untouched.
    const glm::ivec3 bg = px(img, edge - 3 - 8 - 3, y);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(bg[c], 128, 2) << "background at x=" << edge - 14;
    // Same on the right side.
    const int right = edge + stem_w;  // first non-fill pixel
    EXPECT_LT(px(img, right + 1, y).r, 60);
    EXPECT_GT(px(img, right + 5, y).g, 235);
    EXPECT_NEAR(px(img, right + 13, y).b, 128, 2);
}

TEST_F(TextLayerTest, HaloAndOutlineScaleWithTheLabel) {
    begin(256, 160);
    const LaidOutText l = m_engine->layout(m_engine->run("I"), 48.0f);
    TextDraw d;
    d.quads = l.quads;
    d.size_px = l.size_px;
    d.position = {128.0f, 80.0f};
    d.style = bandsStyle();
    d.style.outline_px = 1.5f;
    d.style.halo_px = 4.0f;
    d.scale = 2.0f;  // drawn at 96 px: bands twice as wide, like the test above
    m_layer->drawScreen(std::span(&d, 1), {256, 160});
    const Image img = finish();
    const Box box = inkBox(img, {128, 128, 128});
    ASSERT_FALSE(box.empty());
    // I at 96 px is ~ 70 px tall; + 2 x (3 + 8) px of outline and halo.
    EXPECT_GT(box.h(), 70 + 2 * 8);
    EXPECT_LT(box.h(), 70 + 2 * 13 + 8);
}

TEST_F(TextLayerTest, RotationIsClockwiseAboutTheAnchor) {
    const LaidOutText probe = m_engine->layout(m_engine->run("HHHHHHHH"), 24.0f);
    for (const float deg : {0.0f, 90.0f, 30.0f}) {
        begin(320, 320);
        const LaidOutText l = m_engine->layout(m_engine->run("HHHHHHHH"), 24.0f);
        TextDraw d;
        d.quads = l.quads;
        d.size_px = l.size_px;
        d.position = {160.0f, 160.0f};
        d.angle_rad = glm::radians(deg);
        d.style = bandsStyle();
        d.style.halo_px = 0.0f;
        m_layer->drawScreen(std::span(&d, 1), {320, 320});
        const Image img = finish();
        const Box box = inkBox(img, {128, 128, 128});
        ASSERT_FALSE(box.empty()) << deg;
        const float cx = 0.5f * (box.x0 + box.x1), cy = 0.5f * (box.y0 + box.y1);
        EXPECT_NEAR(cx, 160.0f, 3.0f) << deg;  // rotation about the (centered) anchor
        EXPECT_NEAR(cy, 160.0f, 3.0f) << deg;
        if (deg == 0.0f) {
            EXPECT_NEAR(box.w(), probe.metrics.width, 8.0f);
            EXPECT_GT(box.w(), 3 * box.h());
        } else if (deg == 90.0f) {
            EXPECT_NEAR(box.h(), probe.metrics.width, 8.0f);
            EXPECT_GT(box.h(), 3 * box.w());
        } else {
            // Clockwise on screen (y down): the end of the text goes down to the right.
            const Box right = inkBox(img, {128, 128, 128}, 24, 200, 320);
            ASSERT_FALSE(right.empty());
            EXPECT_GT(0.5f * (right.y0 + right.y1), 160.0f + 15.0f);
        }
    }
}

TEST_F(TextLayerTest, AlphaBlendsOverTheBackground) {
    begin(256, 160);
    const LaidOutText l = m_engine->layout(m_engine->run("I"), 96.0f);
    TextDraw d[2];
    for (TextDraw& x : d) {
        x.quads = l.quads;
        x.size_px = l.size_px;
        x.style.fill = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
        x.style.outline_px = 0.0f;
        x.style.halo_px = 0.0f;
    }
    d[0].position = {64.0f, 80.0f};
    d[0].alpha = 0.5f;
    d[1].position = {192.0f, 80.0f};
    d[1].alpha = 0.0f;  // faded out: nothing drawn
    m_layer->drawScreen(d, {256, 160});
    const Image img = finish();
    const Box half = inkBox(img, {128, 128, 128}, 24, 0, 128);
    ASSERT_FALSE(half.empty());
    const glm::ivec3 c = px(img, (half.x0 + half.x1) / 2, 80);
    EXPECT_NEAR(c.r, 64, 3);   // 0.5 * 0 + 0.5 * 128
    EXPECT_NEAR(c.b, 191, 3);  // 0.5 * 255 + 0.5 * 128
    EXPECT_TRUE(inkBox(img, {128, 128, 128}, 2, 128, 256).empty()) << "alpha 0 must draw nothing";
}

TEST_F(TextLayerTest, WorldLabelsAreHiddenBehindOccludersAndForeshortenWithDistance) {
    const int w = 480, h = 240;
    begin(w, h);
    // Occluder: the left half of the depth buffer is at the near plane.
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, w / 2, h);
    glClearBufferfi(GL_DEPTH_STENCIL, 0, 0.0f, 0);
    glDisable(GL_SCISSOR_TEST);
    const LaidOutText l = m_engine->layout(m_engine->run("Ordino"), 32.0f);
    const glm::mat4 projection = glm::perspective(glm::radians(45.0f), float(w) / h, 1.0f, 20000.0f);
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    WorldTextDraw d[3];
    for (WorldTextDraw& x : d) {
        x.quads = l.quads;
        x.size_px = l.size_px;
        x.em_m = 20.0f;
        x.right = {1.0f, 0.0f, 0.0f};  // facing the camera
        x.up = {0.0f, 1.0f, 0.0f};
        x.style = bandsStyle();
        x.style.halo_px = 2.0f;
    }
    // Left: behind the occluder. Right: the same text near and twice as far.
    d[0].position = {-200.0f, 0.0f, -500.0f};
    d[1].position = {60.0f, 40.0f, -300.0f};
    d[2].position = {300.0f, -60.0f, -600.0f};
    m_layer->drawWorld(d, view, projection, {w, h});
    const Image img = finish();
    EXPECT_TRUE(inkBox(img, {128, 128, 128}, 4, 0, w / 2).empty()) << "label behind the occluder is drawn";
    const Box near = inkBox(img, {128, 128, 128}, 24, w / 2, w / 2 + 120);
    const Box far = inkBox(img, {128, 128, 128}, 24, w / 2 + 120, w);
    ASSERT_FALSE(near.empty());
    ASSERT_FALSE(far.empty());
    // Perspective, no clamping: 20 m em at 300 m with focal 2.414 and 240 px is 19.3 px em, at
    // 600 m half of it (seed 5.2.1: world-space labels are foreshortened with distance).
    const TextMetrics m = measureText(m_engine->shaped(m_engine->run("Ordino")), 1.0f);
    for (const auto& [box, depth] : {std::pair{near, 300.0f}, std::pair{far, 600.0f}}) {
        const float em = 20.0f * projection[1][1] * 0.5f * h / depth;
        EXPECT_NEAR(box.w(), m.width * em + 2 * (3 + 2) * em / 32.0f, 4.0f) << "at " << depth << " m";
    }
    EXPECT_NEAR(static_cast<float>(near.w()) / static_cast<float>(far.w()), 2.0f, 0.3f);
}

TEST_F(TextLayerTest, WorldLabelsReadAlongTheirBaselineDirection) {
    const int w = 480, h = 240;
    begin(w, h);
    const LaidOutText l = m_engine->layout(m_engine->run("Carrer Major"), 32.0f);
    const glm::mat4 projection = glm::perspective(glm::radians(45.0f), float(w) / h, 1.0f, 20000.0f);
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    // A baseline turned 30 degrees up from the screen's x axis, in the plane facing the camera.
    const float a = glm::radians(30.0f);
    WorldTextDraw d;
    d.quads = l.quads;
    d.size_px = l.size_px;
    d.em_m = 14.0f;
    d.right = {std::cos(a), std::sin(a), 0.0f};
    d.up = {-std::sin(a), std::cos(a), 0.0f};
    d.position = {0.0f, 0.0f, -400.0f};
    d.style = bandsStyle();
    m_layer->drawWorld(std::span(&d, 1), view, projection, {w, h});
    const Image img = finish();
    // Fit the ink pixels' principal axis: it follows the baseline (up the screen to the right).
    double sx = 0, sy = 0, n = 0;
    std::vector<glm::dvec2> ink;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::ivec3 c = px(img, x, y);
            if (std::abs(c.r - 128) + std::abs(c.g - 128) + std::abs(c.b - 128) > 24) {
                ink.emplace_back(x, y);
                sx += x;
                sy += y;
                ++n;
            }
        }
    }
    ASSERT_GT(n, 200);
    const glm::dvec2 mean(sx / n, sy / n);
    double cxx = 0, cxy = 0, cyy = 0;
    for (const glm::dvec2 p : ink) {
        const glm::dvec2 q = p - mean;
        cxx += q.x * q.x;
        cxy += q.x * q.y;
        cyy += q.y * q.y;
    }
    const double angle = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);  // y down: negative is up the screen
    EXPECT_NEAR(angle * 180.0 / std::numbers::pi, -30.0, 4.0);
    EXPECT_NEAR(mean.x, w / 2.0, 6.0);
    EXPECT_NEAR(mean.y, h / 2.0, 6.0);
}

TEST_F(TextLayerTest, GoldenLabels) {
    const int w = 480, h = 200;
    begin(w, h);
    // A busy background: stripes of land-cover-like colours under the labels.
    glEnable(GL_SCISSOR_TEST);
    const float stripes[][4] = {{0.55f, 0.70f, 0.45f, 1.0f},
                                {0.85f, 0.85f, 0.80f, 1.0f},
                                {0.40f, 0.55f, 0.80f, 1.0f},
                                {0.30f, 0.30f, 0.30f, 1.0f}};
    for (int i = 0; i < 4; ++i) {
        glScissor(i * w / 4, 0, w / 8, h);
        glClearBufferfv(GL_COLOR, 0, stripes[i]);
    }
    glDisable(GL_SCISSOR_TEST);
    using navmap::map::LabelKind;
    using navmap::map::PlaceClass;
    struct Item {
        LabelKind kind;
        std::uint8_t sub;
        const char* text;
        glm::vec2 pos;
        float angle_deg;
        float alpha;
    };
    const Item items[] = {
        {LabelKind::Place, static_cast<std::uint8_t>(PlaceClass::Town), "Andorra la Vella", {140, 30}, 0, 1},
        {LabelKind::Place, static_cast<std::uint8_t>(PlaceClass::Village), "Sant Julià de Lòria", {340, 60}, 0, 1},
        {LabelKind::Poi, 2, "Museu del Tabac", {120, 90}, 0, 1},
        {LabelKind::Road, 3, "Avinguda Meritxell", {330, 125}, -20, 1},
        {LabelKind::Area,
         static_cast<std::uint8_t>(navmap::map::AreaClass::Water),
         "Estany d'Engolasters",
         {120, 150},
         0,
         1},
        {LabelKind::Poi, 0, "利奥尔茨小镇停车场", {340, 178}, 0, 1},
        {LabelKind::Place, static_cast<std::uint8_t>(PlaceClass::Hamlet), "Col·legi (fading)", {110, 185}, 0, 0.5f},
    };
    std::vector<LaidOutText> laid;
    std::vector<TextDraw> draws;
    for (const Item& it : items) {
        const LabelTextStyle s = labelTextStyle(it.kind, it.sub);
        const RunId run = m_engine->run(it.text, s.font);
        laid.push_back(s.icon.empty() ? m_engine->layout(run, s.size_px)
                                      : m_engine->layoutWithIcon(m_engine->run(s.icon, s.font), run, s.size_px));
        EXPECT_EQ(laid.back().dropped, 0u);
        EXPECT_EQ(m_engine->shaped(run).missing, 0u) << it.text;
    }
    for (std::size_t i = 0; i < laid.size(); ++i) {
        const LabelTextStyle s = labelTextStyle(items[i].kind, items[i].sub);
        TextDraw d;
        d.quads = laid[i].quads;
        d.size_px = laid[i].size_px;
        d.position = items[i].pos;
        d.angle_rad = glm::radians(items[i].angle_deg);
        d.alpha = items[i].alpha;
        d.style = s.style;
        draws.push_back(d);
    }
    m_layer->drawScreen(draws, {w, h});
    const Image img = finish();
    // llvmpipe is deterministic here; a little room for other Mesa versions' filtering.
    EXPECT_GOLDEN(img, "render/text/golden/labels.png", (navmap::test::GoldenTolerance{12, 0.01}));
}

}  // namespace
