#version 450 core
// Test shader (tests/gl): writes one uniform colour to every covered pixel.
uniform vec4 colour;
layout(location = 0) out vec4 outColour;

void main() {
    outColour = colour;
}
