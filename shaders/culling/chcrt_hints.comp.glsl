#version 450 core
// CHC+RT hint pass (culling/hint_pass.h) as a compute pass: one invocation per pixel, inactive rays return at once.
// For GPUs whose fragment work runs on few units. Host defines: hint_pass.glsl's.
#include "culling/hint_pass.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

uniform ivec2 raySize; // pixels of the ray set

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, raySize))) {
        return;
    }
    visitHintOfPixel(pixel);
}
