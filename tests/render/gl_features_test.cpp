// SPDX-License-Identifier: Apache-2.0
// What the renderer turns off on a GL ES context that offers less than ES 3.2 (docs/gles-profile.md):
// decided from the version and the extension list, without a context.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gl/gl_features.h"

namespace {

using navmap::render::gl::GlFeatures;

const std::string kSvOff = "shadow-volume roads (no GL_EXT_color_buffer_float before ES 3.2): geometric roads";

TEST(GlFeatures, FloatColourBuffersAreCoreInEs32AndAnExtensionBefore) {
    const std::vector<std::string> none;
    const std::vector<std::string> ext = {"GL_KHR_debug", "GL_EXT_color_buffer_float", "GL_OES_texture_float_linear"};
    EXPECT_TRUE(GlFeatures(3, 2, none, 4).colorBufferFloat());
    EXPECT_TRUE(GlFeatures(3, 0, ext, 4).colorBufferFloat());
    EXPECT_TRUE(GlFeatures(3, 1, ext, 4).colorBufferFloat());
    EXPECT_FALSE(GlFeatures(3, 0, none, 4).colorBufferFloat());
    EXPECT_FALSE(GlFeatures(3, 1, none, 4).colorBufferFloat());
    // Whole names only: the half-float extension does not make R32F renderable.
    const std::vector<std::string> half = {"GL_EXT_color_buffer_half_float", "GL_EXT_color_buffer_float_x"};
    EXPECT_FALSE(GlFeatures(3, 0, half, 4).colorBufferFloat());
    EXPECT_TRUE(GlFeatures(3, 0, ext, 4).hasExtension("GL_KHR_debug"));
    EXPECT_FALSE(GlFeatures(3, 0, ext, 4).hasExtension("GL_KHR"));
}

TEST(GlFeatures, Es30WithoutFloatColourBuffersTurnsOffShadowVolumeRoadsOnly) {
    const std::vector<std::string> none;
    EXPECT_EQ(GlFeatures(3, 0, none, 4).featuresOff(4, false), std::vector<std::string>{kSvOff});
    EXPECT_EQ(GlFeatures(3, 1, none, 4).featuresOff(0, false), std::vector<std::string>{kSvOff});
    EXPECT_TRUE(GlFeatures(3, 2, none, 4).featuresOff(4, false).empty());
    const std::vector<std::string> ext = {"GL_EXT_color_buffer_float"};
    EXPECT_TRUE(GlFeatures(3, 0, ext, 8).featuresOff(-1, false).empty());
}

TEST(GlFeatures, MsaaOffOrFewerSamplesAreListed) {
    const std::vector<std::string> ext = {"GL_EXT_color_buffer_float"};
    // Auto: off on a software rasterizer, 4x on a GPU.
    EXPECT_EQ(GlFeatures(3, 2, ext, 4).featuresOff(-1, true),
              std::vector<std::string>{"MSAA (software rasterizer, msaa auto): no multisampling"});
    EXPECT_TRUE(GlFeatures(3, 2, ext, 4).featuresOff(-1, false).empty());
    EXPECT_EQ(GlFeatures(3, 0, ext, 0).featuresOff(-1, false),
              std::vector<std::string>{"MSAA (GL_MAX_SAMPLES 0): no multisampling"});
    // Asked for more than the driver has: clamped.
    EXPECT_EQ(GlFeatures(3, 0, ext, 4).featuresOff(8, true),
              std::vector<std::string>{"MSAA 8x (GL_MAX_SAMPLES 4): 4x"});
    // Off by choice is not a feature the context lacks.
    EXPECT_TRUE(GlFeatures(3, 0, ext, 0).featuresOff(0, true).empty());
    EXPECT_TRUE(GlFeatures(3, 0, ext, 4).featuresOff(4, true).empty());
    // Both at once, float colour buffers first.
    const std::vector<std::string> none;
    EXPECT_EQ(GlFeatures(3, 0, none, 1).featuresOff(4, false),
              (std::vector<std::string>{kSvOff, "MSAA (GL_MAX_SAMPLES 1): no multisampling"}));
}

}  // namespace
