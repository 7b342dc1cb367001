// The vertex normals by original id (shared/render_layout.h), read by the traced G-buffer's resolve.
// Parts: render/triangle_parts.glsl.
#ifndef CHCRT_VERTEX_NORMALS_GLSL
#define CHCRT_VERTEX_NORMALS_GLSL
#include "render/triangle_parts.glsl"

layout(binding = CHCRT_UNIT_TRI_NORMALS) uniform usamplerBuffer triangleNormals;
#if CHCRT_TRIANGLE_BUFFERS > 1
layout(binding = CHCRT_UNIT_TRI_NORMALS_PART1) uniform usamplerBuffer triangleNormals1;
#endif
#if CHCRT_TRIANGLE_BUFFERS > 2
layout(binding = CHCRT_UNIT_TRI_NORMALS_PART1 + 1) uniform usamplerBuffer triangleNormals2;
#endif
#if CHCRT_TRIANGLE_BUFFERS > 3
layout(binding = CHCRT_UNIT_TRI_NORMALS_PART1 + 2) uniform usamplerBuffer triangleNormals3;
#endif

// Texel `texel` of the vertex normals by original id (CHCRT_NORMAL_TEXELS_PER_TRIANGLE per triangle).
uvec4 normalTexel(int texel) {
#if CHCRT_TRIANGLE_BUFFERS > 1
    int size = textureSize(triangleNormals);
    if (texel >= size) {
        texel -= size;
#if CHCRT_TRIANGLE_BUFFERS > 2
        if (texel >= size) {
            texel -= size;
#if CHCRT_TRIANGLE_BUFFERS > 3
            if (texel >= size) {
                return texelFetch(triangleNormals3, texel - size);
            }
#endif
            return texelFetch(triangleNormals2, texel);
        }
#endif
        return texelFetch(triangleNormals1, texel);
    }
#endif
    return texelFetch(triangleNormals, texel);
}
#endif
