#pragma once
// The shader sources embedded at build time (cmake/EmbedShaders.cmake); terminated by {nullptr, nullptr}.
namespace chcrt {
struct EmbeddedShader {
    const char* path; // relative to shaders/
    const char* text;
};
const EmbeddedShader* embeddedShaders();
} // namespace chcrt
