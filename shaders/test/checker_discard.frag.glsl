#version 450 core
// Test shader (tests/gl): keeps only pixels with even x + y, so an occlusion query has a known, non-trivial
// count.
layout(location = 0) out vec4 outColour;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (((pixel.x + pixel.y) & 1) != 0) {
        discard;
    }
    outColour = vec4(1.0f);
}
