// The per-triangle attributes by original id (shared/render_layout.h), read by render/material.glsl.
// Parts: render/triangle_parts.glsl.
#ifndef CHCRT_TRIANGLE_ATTRIBUTES_GLSL
#define CHCRT_TRIANGLE_ATTRIBUTES_GLSL
#include "render/triangle_parts.glsl"

layout(binding = CHCRT_UNIT_TRI_ATTRIBUTES) uniform samplerBuffer triangleAttributes;
#if CHCRT_TRIANGLE_BUFFERS > 1
layout(binding = CHCRT_UNIT_TRI_ATTRIBUTES_PART1) uniform samplerBuffer triangleAttributes1;
#endif
#if CHCRT_TRIANGLE_BUFFERS > 2
layout(binding = CHCRT_UNIT_TRI_ATTRIBUTES_PART1 + 1) uniform samplerBuffer triangleAttributes2;
#endif
#if CHCRT_TRIANGLE_BUFFERS > 3
layout(binding = CHCRT_UNIT_TRI_ATTRIBUTES_PART1 + 2) uniform samplerBuffer triangleAttributes3;
#endif

// Texel `texel` of the attributes by original id (CHCRT_ATTR_TEXELS_PER_TRIANGLE per triangle).
vec4 attributeTexel(int texel) {
#if CHCRT_TRIANGLE_BUFFERS > 1
    int size = textureSize(triangleAttributes);
    if (texel >= size) {
        texel -= size;
#if CHCRT_TRIANGLE_BUFFERS > 2
        if (texel >= size) {
            texel -= size;
#if CHCRT_TRIANGLE_BUFFERS > 3
            if (texel >= size) {
                return texelFetch(triangleAttributes3, texel - size);
            }
#endif
            return texelFetch(triangleAttributes2, texel);
        }
#endif
        return texelFetch(triangleAttributes1, texel);
    }
#endif
    return texelFetch(triangleAttributes, texel);
}
#endif
