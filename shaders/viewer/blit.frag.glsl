#version 450 core
// Draws the display image (linear display values, internal resolution) to the window, bilinearly scaled, with
// the sRGB transfer function applied here: the default framebuffer is not assumed to be sRGB-capable, and
// this matches what writeImage does for PNG screenshots.
#include "shared/viewer_layout.h"

layout(binding = CHCRT_VIEWER_UNIT_SOURCE) uniform sampler2D displayImage;
in vec2 screenUv;
layout(location = 0) out vec4 outColour;

vec3 encodeSrgb(vec3 linear) {
    vec3 c = clamp(linear, 0.0f, 1.0f);
    return mix(12.92f * c, 1.055f * pow(c, vec3(1.0f / 2.4f)) - 0.055f, step(vec3(0.0031308f), c));
}

void main() {
    outColour = vec4(encodeSrgb(texture(displayImage, screenUv).rgb), 1.0f);
}
