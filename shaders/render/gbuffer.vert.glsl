#version 450 core
// G-buffer rasterisation (primary visibility): world-space triangles in BVH order, one indirect draw per cluster
// (BVH subtree) inside the frustum (renderer/render/scene_gpu.cpp). The cluster's first BVH-order triangle comes
// in as a per-instance attribute; the fragment shader adds gl_PrimitiveID to find the triangle.
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inTexcoord;
layout(location = 3) in uint inClusterFirst;

uniform mat4 clipFromWorld;

out vec3 worldPosition;
out vec3 worldNormal;
out vec2 texcoord;
flat out uint clusterFirst;

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    texcoord = inTexcoord;
    clusterFirst = inClusterFirst;
    gl_Position = clipFromWorld * vec4(inPosition, 1.0f);
}
