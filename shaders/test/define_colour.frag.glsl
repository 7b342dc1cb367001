#version 450 core
// Test shader (tests/gl): the colour comes from host #defines, proving they reach the compiler after #version.
// Host defines: RED, GREEN (floats), optional USE_BLUE.
layout(location = 0) out vec4 outColour;

void main() {
#ifdef USE_BLUE
    float blue = 1.0f;
#else
    float blue = 0.0f;
#endif
    outColour = vec4(RED, GREEN, blue, 1.0f);
}
