// Material and per-triangle attribute lookups shared by the G-buffer pass and hit shading.
// Layouts: shaders/shared/render_layout.h (CHCRT_MATERIAL_TEXELS, CHCRT_ATTR_TEXELS_PER_TRIANGLE).
#include "render/triangle_attributes.glsl"
layout(binding = CHCRT_UNIT_MATERIALS) uniform samplerBuffer materials;
layout(binding = CHCRT_UNIT_BASE_COLOR) uniform sampler2DArray baseColorTextures;

// Linear base colour of a material at a texture coordinate (the texture array is SRGB8_ALPHA8, so sampling
// decodes to linear).
// lod < 0 selects the mip level from screen-space derivatives (rasterisation); hit shading in full-screen
// passes has no meaningful derivatives and passes an explicit level.
vec3 materialAlbedo(uint materialId, vec2 uv, float lod) {
    vec4 factor = texelFetch(materials, int(materialId) * CHCRT_MATERIAL_TEXELS);
    vec4 texInfo = texelFetch(materials, int(materialId) * CHCRT_MATERIAL_TEXELS + 1);
    vec3 albedo = factor.rgb;
    if (texInfo.x >= 0.0f) {
        vec3 coord = vec3(uv * texInfo.yz, texInfo.x);
        albedo *= (lod < 0.0f ? texture(baseColorTextures, coord) : textureLod(baseColorTextures, coord, lod)).rgb;
    }
    return albedo;
}

// Albedo and geometric normal at a traced hit (original triangle id, barycentrics u, v).
vec3 hitAlbedo(uint triangleId, vec2 barycentrics) {
    int base = int(triangleId) * CHCRT_ATTR_TEXELS_PER_TRIANGLE;
    vec4 attr0 = attributeTexel(base);
    vec4 attr1 = attributeTexel(base + 1);
    vec4 attr2 = attributeTexel(base + 2);
    vec2 uv = (1.0f - barycentrics.x - barycentrics.y) * attr1.xy + barycentrics.x * attr1.zw +
              barycentrics.y * attr2.xy;
    return materialAlbedo(floatBitsToUint(attr0.w), uv, 1.0f);
}
vec3 hitGeometricNormal(uint triangleId) {
    return attributeTexel(int(triangleId) * CHCRT_ATTR_TEXELS_PER_TRIANGLE).xyz;
}
