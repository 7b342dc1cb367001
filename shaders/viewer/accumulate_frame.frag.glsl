#version 450 core
// Progressive refinement: adds one frame's linear HDR radiance to the viewer's sum (additive blending; alpha
// is 1 per frame, so the sum's alpha counts frames).
#include "shared/viewer_layout.h"

layout(binding = CHCRT_VIEWER_UNIT_SOURCE) uniform sampler2D frameHdr;
layout(location = 0) out vec4 outSum;

void main() {
    outSum = vec4(texelFetch(frameHdr, ivec2(gl_FragCoord.xy), 0).rgb, 1.0f);
}
