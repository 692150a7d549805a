// SPDX-License-Identifier: Apache-2.0
// Terrain shading: hypsometric tint, replaced by the tile's land-cover raster where it has
// coverage, times relief shading; aerial perspective towards the horizon. Tint, shading and fog
// come per vertex (they vary smoothly, and on llvmpipe every per-pixel instruction is CPU time).
// The land-cover texture is the pluggable input: TerrainPass binds the tile's synthetic orthoimage
// in its place (MapStyle::ground; opaque, so the tint does not show through).
#ifndef NAVMAP_COVER_LEVELS
#define NAVMAP_COVER_LEVELS 1  // land-cover levels blended (terrain_tile.frag)
#endif
in vec2 v_uv;
in vec3 v_tint;    // hypsometric tint, per vertex (terrain_tile.vert)
in float v_shade;  // relief shading and brightness, times the ground's share against the fog
in vec3 v_sky;     // aerial perspective: the sky colour times its share

uniform sampler2D u_land_cover;
#if NAVMAP_COVER_LEVELS > 1
// Geomorphing of the land cover (terrain_lod.h): the rasters of the parent and the grandparent
// over this tile's square (same texel grid as their own rasters) blend in like the surface,
//     C_L(d) = mix(c_L, mix(c_L-1, c_L-2, f_L-1(d)), f_L(d)),
// so where the surface has become the parent's, the land cover is the parent's too and a level
// switch changes neither. The rasters are premultiplied, so a level without coverage at a place
// fades the cover out instead of darkening it. Each texture fetch costs about a quarter of the
// terrain pass on llvmpipe, so a tile gets only the levels its distances reach
// (NAVMAP_COVER_LEVELS 2 or 3, the finest of them in u_land_cover); the grandparent stands in
// for the coarser levels of slots 2 and 3.
uniform sampler2D u_cover1;  // one level coarser than u_land_cover
#if NAVMAP_COVER_LEVELS == 3
uniform sampler2D u_cover2;  // two levels coarser
#endif
in vec2 v_cover_morph;  // the factors from u_land_cover to u_cover1 and from u_cover1 to u_cover2
#endif

layout(location = 0) out vec4 o_color;
// Shadow-volume roads (seed 3.5.2): the terrain's view-space depth as a secondary target. Only
// stored where a framebuffer binds draw buffer 3 (SvRoads); 1 / gl_FragCoord.w is the clip w,
// i.e. the exact view depth of this fragment, without an extra varying.
layout(location = 3) out vec4 o_terrain_depth;


void main() {
#if NAVMAP_COVER_LEVELS == 3
    vec4 coarser = mix(texture(u_cover1, v_uv), texture(u_cover2, v_uv), v_cover_morph.y);
    vec4 cover = mix(texture(u_land_cover, v_uv), coarser, v_cover_morph.x);
#elif NAVMAP_COVER_LEVELS == 2
    vec4 cover = mix(texture(u_land_cover, v_uv), texture(u_cover1, v_uv), v_cover_morph.x);
#else
    vec4 cover = texture(u_land_cover, v_uv);
#endif
    vec3 base = v_tint * (1.0 - cover.a) + cover.rgb;  // the cover is premultiplied
    o_color = vec4(base * v_shade + v_sky, 1.0);
    o_terrain_depth = vec4(1.0 / gl_FragCoord.w, 0.0, 0.0, 0.0);
}
