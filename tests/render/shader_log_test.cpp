// SPDX-License-Identifier: Apache-2.0
// Driver compile logs are rewritten to name the shader file and line.
#include <gtest/gtest.h>

#include "gl/shader_program.h"

namespace {

using navmap::render::gl::annotateShaderLog;

TEST(ShaderLog, MesaLocations) {
    EXPECT_EQ(annotateShaderLog("0:12(5): error: `x' undeclared\n", "roads_geo.frag"),
              "roads_geo.frag:12:5: error: `x' undeclared");
}

TEST(ShaderLog, NvidiaLocations) {
    EXPECT_EQ(annotateShaderLog("0(7) : error C1008: undefined variable \"x\"", "a.vert"),
              "a.vert:7 : error C1008: undefined variable \"x\"");
}

TEST(ShaderLog, AngleLocationsOnEveryLine) {
    EXPECT_EQ(annotateShaderLog("ERROR: 0:3: 'x' : undeclared\nERROR: 0:9: '' : syntax error", "t.frag"),
              "t.frag:3: ERROR: 'x' : undeclared\nt.frag:9: ERROR: '' : syntax error");
}

}  // namespace
