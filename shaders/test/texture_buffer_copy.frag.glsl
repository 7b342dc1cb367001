#version 450 core
// Test shader (tests/gl): copies texel (y * width + x) of an RGBA32F texture buffer to pixel (x, y); pixels past
// the end get -1.
layout(binding = 0) uniform samplerBuffer source;
uniform int width;
uniform int texelCount;
layout(location = 0) out vec4 outColour;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int index = pixel.y * width + pixel.x;
    outColour = index < texelCount ? texelFetch(source, index) : vec4(-1.0f);
}
