#version 450 core
// G-buffer rasterisation (primary visibility): world-space triangle soup, one draw call over all triangles
// in scene order, so gl_PrimitiveID in the fragment shader is the original triangle id.
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inTexcoord;

uniform mat4 clipFromWorld;

out vec3 worldPosition;
out vec3 worldNormal;
out vec2 texcoord;

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    texcoord = inTexcoord;
    gl_Position = clipFromWorld * vec4(inPosition, 1.0f);
}
