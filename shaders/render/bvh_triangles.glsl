// The BVH-ordered triangles (shared/bvh_layout.h), read by every traversal and by the G-buffer pass.
// Parts: render/triangle_parts.glsl.
#ifndef CHCRT_BVH_TRIANGLES_GLSL
#define CHCRT_BVH_TRIANGLES_GLSL
#include "render/triangle_parts.glsl"

layout(binding = CHCRT_UNIT_BVH_TRIANGLES) uniform samplerBuffer bvhTriangles;
#if CHCRT_TRIANGLE_BUFFERS > 1
layout(binding = CHCRT_UNIT_BVH_TRIANGLES_PART1) uniform samplerBuffer bvhTriangles1;
#endif
#if CHCRT_TRIANGLE_BUFFERS > 2
layout(binding = CHCRT_UNIT_BVH_TRIANGLES_PART1 + 1) uniform samplerBuffer bvhTriangles2;
#endif
#if CHCRT_TRIANGLE_BUFFERS > 3
layout(binding = CHCRT_UNIT_BVH_TRIANGLES_PART1 + 2) uniform samplerBuffer bvhTriangles3;
#endif

// Texel `texel` of the BVH-ordered triangles (CHCRT_TRI_TEXELS_PER_TRIANGLE per triangle).
vec4 triangleTexel(int texel) {
#if CHCRT_TRIANGLE_BUFFERS > 1
    int size = textureSize(bvhTriangles);
    if (texel >= size) {
        texel -= size;
#if CHCRT_TRIANGLE_BUFFERS > 2
        if (texel >= size) {
            texel -= size;
#if CHCRT_TRIANGLE_BUFFERS > 3
            if (texel >= size) {
                return texelFetch(bvhTriangles3, texel - size);
            }
#endif
            return texelFetch(bvhTriangles2, texel);
        }
#endif
        return texelFetch(bvhTriangles1, texel);
    }
#endif
    return texelFetch(bvhTriangles, texel);
}
#endif
