#version 450 core
// One triangle that covers the viewport, positions derived from gl_VertexID (no vertex buffers; draw with
// drawFullscreenTriangle()). Vertices (-1,-1), (3,-1), (-1,3) in clip space: the part outside [-1,1]^2 is
// clipped, and unlike a two-triangle quad there is no diagonal seam where fragments are shaded twice.
// Fragment shaders address pixels with gl_FragCoord; screenUv is [0,1]^2 across the viewport.
out vec2 screenUv;

void main() {
    vec2 position = vec2(float((gl_VertexID & 1) << 2) - 1.0f, float((gl_VertexID & 2) << 1) - 1.0f);
    screenUv = position * 0.5f + 0.5f;
    gl_Position = vec4(position, 0.0f, 1.0f);
}
