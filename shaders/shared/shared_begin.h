// Included first by every header shared between C++ and GLSL (nvpro-samples style): in C++ it opens the
// chcrt::gpu namespace with GLM types standing in for GLSL's; in GLSL it does nothing.
#ifdef __cplusplus
#include <glm/glm.hpp>
#include <cstdint>
namespace chcrt::gpu {
using glm::ivec2;
using glm::ivec4;
using glm::uvec2;
using glm::uvec4;
using glm::vec2;
using glm::vec3;
using glm::vec4;
using uint = uint32_t;
#endif
