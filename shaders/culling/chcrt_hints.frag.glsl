#version 450 core
// CHC+RT hint pass (culling/hint_pass.h) as a fragment pass: a full-screen triangle over the ray set's active-ray
// mask, so that the early depth test skips inactive rays as in the pure passes (on llvmpipe the compute pass, which
// must look at every pixel, measured slower). No colour output. Host defines: hint_pass.glsl's.
#include "culling/hint_pass.glsl"

layout(early_fragment_tests) in;

void main() {
    visitHintOfPixel(ivec2(gl_FragCoord.xy));
}
