// Twin test of shaders/shared/linespace_layout.h: the GLSL build (shaders/linespace/shaft_index_twin.frag.glsl,
// one case per pixel) against the C++ build of the same text over seeded random rays and boxes (cubes, BVH-like
// boxes, flat boxes; origins inside and outside; axis-parallel directions; rays through edges, corners and patch
// boundaries), and the sparse slot of Algorithm 2 over random bitset words.
#include "linespace/linespace_build.h"
#include "linespace/shaft_index.h"
#include "renderer/core/error.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "shaders/shared/linespace_layout.h"
#include "tests/gl/gl_test_fixture.h"
#include "tests/linespace/linespace_test_util.h"

#include <cmath>
#include <cstring>
#include <utility>

namespace chcrt {
namespace {

using glm::vec3;
using test::GlTest;

constexpr int kWidth = 128, kHeight = 64, kCases = kWidth * kHeight;

struct Case {
    vec3 origin, direction, boxMin, boxMax;
    uint32_t n, word, offset, shaft;
};

uint32_t floatBitsToUint(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof(u));
    return u;
}

float bitsToFloat(uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof(f));
    return f;
}

std::vector<Case> makeCases() {
    test::Rng rng{4242};
    std::vector<Case> cases;
    while (static_cast<int>(cases.size()) < kCases) {
        const int i = static_cast<int>(cases.size());
        Case c{};
        c.n = 1 + rng.below(10);
        const vec3 centre = rng.uniform3(-100.0f, 100.0f);
        vec3 half = i % 4 == 0 ? vec3(rng.uniform(0.1f, 10.0f)) : rng.uniform3(0.01f, 10.0f);
        if (i % 9 == 0) {
            half[static_cast<int>(rng.below(3))] = 0.0f; // flat box
        }
        c.boxMin = centre - half;
        c.boxMax = centre + half;
        // Targets on patch boundaries, edges and corners for a quarter of the cases.
        vec3 target = rng.uniform3(c.boxMin, c.boxMax);
        if (i % 4 == 1) {
            for (int a = 0; a < 3; ++a) {
                const float k = static_cast<float>(rng.below(c.n + 1)) / static_cast<float>(c.n);
                target[a] = c.boxMin[a] + k * (c.boxMax[a] - c.boxMin[a]);
            }
        }
        c.origin = i % 3 == 0 ? rng.uniform3(c.boxMin, c.boxMax) : centre + rng.uniform3(-50.0f, 50.0f);
        c.direction = target - c.origin;
        if (i % 8 == 2) {
            c.direction[static_cast<int>(rng.below(3))] = 0.0f;
        } else if (i % 16 == 5) {
            c.direction = vec3(0.0f);
            c.direction[static_cast<int>(rng.below(3))] = rng.uniform(-1.0f, 1.0f) < 0.0f ? -1.0f : 1.0f;
        }
        if (c.direction == vec3(0.0f)) {
            continue;
        }
        c.word = rng.next() & rng.next(); // about a quarter of the bits set
        c.offset = rng.below(1u << 20);
        c.shaft = rng.next();
        cases.push_back(c);
    }
    return cases;
}

// GLSL 4.50 (§4.7.1) gives division and its reciprocal 2.5 ULP of error, where the C++ twin divides correctly
// rounded: a float within 2.5 ULP of the exact quotient lies within 3 steps of the correctly rounded one. The twin's
// divisions are the inverse direction (safeInverseDirection) and the patch coordinate ((x - lo) / extent), so a GLSL
// result that differs from the C++ one is tolerated only when the same C++ code gives it for inputs moved by at most
// kUlps float steps: every combination for the inverse direction's components, one corner component at a time for
// the box (moving the extent and the offset by as much as the division may err). llvmpipe divides correctly
// rounded and needs none of it; the tolerance exists for drivers that use approximate reciprocals.
constexpr int kUlps = 3;

float stepped(float value, int steps) {
    for (int i = 0; i < std::abs(steps); ++i) value = std::nextafter(value, steps > 0 ? INFINITY : -INFINITY);
    return value;
}

// Whether `result(origin, direction or invDir, boxMin, boxMax)` (the C++ twin) gives `gpu` for inputs within the
// bound above. `vector` is perturbed in every combination, the box one component at a time.
template <typename T, typename F>
bool explainedByDivisionError(const T& gpu, const vec3& vector, const vec3& boxMin, const vec3& boxMax, F result) {
    for (int x = -kUlps; x <= kUlps; ++x) {
        for (int y = -kUlps; y <= kUlps; ++y) {
            for (int z = -kUlps; z <= kUlps; ++z) {
                const vec3 moved(stepped(vector.x, x), stepped(vector.y, y), stepped(vector.z, z));
                if (result(moved, boxMin, boxMax) == gpu) return true;
            }
        }
    }
    for (int corner = 0; corner < 6; ++corner) {
        for (int steps = -kUlps; steps <= kUlps; ++steps) {
            vec3 lo = boxMin, hi = boxMax;
            vec3& moved = corner < 3 ? lo : hi;
            moved[corner % 3] = stepped(moved[corner % 3], steps);
            if (result(vector, lo, hi) == gpu) return true;
        }
    }
    return false;
}

std::vector<glm::uvec4> readTextureRgba32ui(GLuint texture, int width, int height) {
    std::vector<glm::uvec4> texels(static_cast<size_t>(width) * static_cast<size_t>(height));
    glGetTextureImage(texture, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                      static_cast<GLsizei>(texels.size() * sizeof(glm::uvec4)), texels.data());
    checkGlErrors("readTextureRgba32ui");
    return texels;
}

void checkShaftIndexTwin(const std::vector<ShaderDefine>& defines) {
    const std::vector<Case> cases = makeCases();
    std::vector<glm::vec4> texels;
    for (const Case& c : cases) {
        texels.emplace_back(c.origin, 0.0f);
        texels.emplace_back(c.direction, 0.0f);
        texels.emplace_back(c.boxMin, 0.0f);
        texels.emplace_back(c.boxMax, 0.0f);
        texels.emplace_back(bitsToFloat(c.n), bitsToFloat(c.word), bitsToFloat(c.offset), bitsToFloat(c.shaft));
    }
    TextureBuffer input = createTextureBuffer(texels.data(), texels.size() * sizeof(glm::vec4), GL_RGBA32F);
    GlTexture patchesOut = createTexture2D(kWidth, kHeight, GL_RGBA32UI);
    GlTexture shaftsOut = createTexture2D(kWidth, kHeight, GL_RGBA32UI);
    const GLuint targets[2] = {patchesOut.id(), shaftsOut.id()};
    GlFramebuffer framebuffer = createFramebuffer(targets, 2);
    ShaderProgram program({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                           {GL_FRAGMENT_SHADER, "linespace/shaft_index_twin.frag.glsl"}},
                          defines);
    program.set("width", kWidth);
    program.set("caseCount", kCases);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, kWidth, kHeight);
    program.use();
    glBindTextureUnit(0, input.texture.id());
    drawFullscreenTriangle();
    checkGlErrors("shaft index twin draw");
    const std::vector<glm::uvec4> gpuPatches = readTextureRgba32ui(patchesOut.id(), kWidth, kHeight);
    const std::vector<glm::uvec4> gpuShafts = readTextureRgba32ui(shaftsOut.id(), kWidth, kHeight);

    int hits = 0, misses = 0, mismatches = 0, tolerated = 0, slotsFilled = 0;
    for (int i = 0; i < kCases; ++i) {
        const Case& c = cases[static_cast<size_t>(i)];
        // Both outputs of the C++ twin for an inverse direction and a box (the divisions' inputs, see kUlps);
        // patches of a miss compare by their miss mark alone.
        const auto twin = [&c](const vec3& invDir, const vec3& boxMin, const vec3& boxMax) {
            glm::uvec4 patches = gpu::lsEntryExitPatches(c.origin, c.direction, invDir, boxMin, boxMax, c.n);
            if (patches.x == CHCRT_LS_NO_SHAFT) patches = glm::uvec4(CHCRT_LS_NO_SHAFT, 0u, 0u, 0u);
            const glm::uvec4 shafts(gpu::lsShaftIndex(c.origin, c.direction, invDir, boxMin, boxMax, c.n, false),
                                    gpu::lsShaftIndex(c.origin, c.direction, invDir, boxMin, boxMax, c.n, true),
                                    gpu::lsSparseSlot(c.word, c.offset, c.shaft), 0u);
            return std::make_pair(patches, shafts);
        };
        const vec3 invDir = gpu::safeInverseDirection(c.direction);
        const auto [patches, shafts] = twin(invDir, c.boxMin, c.boxMax);
        (patches.x == CHCRT_LS_NO_SHAFT ? misses : hits)++;
        slotsFilled += shafts.z != CHCRT_LS_EMPTY_SLOT ? 1 : 0;
        // Every other operation is a correctly rounded IEEE operation (the products are `precise` in GLSL), so the
        // builds agree exactly, including at edges, corners and patch boundaries, up to the divisions' bound.
        glm::uvec4 g = gpuPatches[static_cast<size_t>(i)];
        if (g.x == CHCRT_LS_NO_SHAFT) g = glm::uvec4(CHCRT_LS_NO_SHAFT, 0u, 0u, 0u);
        const std::pair<glm::uvec4, glm::uvec4> gpuResult(g, gpuShafts[static_cast<size_t>(i)]);
        if (gpuResult != std::make_pair(patches, shafts)) {
            if (explainedByDivisionError(gpuResult, invDir, c.boxMin, c.boxMax, twin)) {
                ++tolerated;
                continue;
            }
            if (++mismatches <= 5) {
                const glm::uvec4 gs = gpuShafts[static_cast<size_t>(i)];
                ADD_FAILURE() << "case " << i << ": GLSL patches (" << g.x << ", " << g.y << ", " << g.z << ", " << g.w
                              << ") shafts (" << gs.x << ", " << gs.y << ", " << gs.z << ") vs C++ (" << patches.x << ", "
                              << patches.y << ", " << patches.z << ", " << patches.w << ") (" << shafts.x << ", "
                              << shafts.y << ", " << shafts.z << ")";
            }
        }
    }
    std::printf("[ twin     ] %d cases: %d hit the box, %d miss; %d filled sparse slots; %d mismatches, %d within "
                "GLSL's division bound\n", kCases, hits, misses, slotsFilled, mismatches, tolerated);
    EXPECT_LE(tolerated, kCases / 100); // rounding at boundaries, not a different classification
    EXPECT_GT(hits, kCases / 2);
    EXPECT_GT(misses, kCases / 20);
    EXPECT_GT(slotsFilled, kCases / 8);
    EXPECT_EQ(mismatches, 0);
}

TEST_F(GlTest, ShaftIndexGlslMatchesCppTwin) { checkShaftIndexTwin({}); }

// The tolerance accepts what a division error within the bound gives, and nothing else.
TEST(ShaftIndexTwinTolerance, AcceptsOnlyResultsWithinTheDivisionBound) {
    int boundaryCases = 0;
    for (const Case& c : makeCases()) {
        const auto twin = [&c](const vec3& invDir, const vec3& boxMin, const vec3& boxMax) {
            return gpu::lsShaftIndex(c.origin, c.direction, invDir, boxMin, boxMax, c.n, false);
        };
        const vec3 invDir = gpu::safeInverseDirection(c.direction);
        const uint32_t exact = twin(invDir, c.boxMin, c.boxMax);
        if (exact == CHCRT_LS_NO_SHAFT) continue;
        EXPECT_FALSE(explainedByDivisionError(exact + 7919u, invDir, c.boxMin, c.boxMax, twin));
        const vec3 off(stepped(invDir.x, 2), stepped(invDir.y, -2), stepped(invDir.z, 1));
        const uint32_t rounded = twin(off, c.boxMin, c.boxMax);
        if (rounded == exact) continue;
        ++boundaryCases; // a ray on a patch boundary: 2 ulps of 1/d move it to the neighbour shaft
        EXPECT_TRUE(explainedByDivisionError(rounded, invDir, c.boxMin, c.boxMax, twin));
    }
    EXPECT_GT(boundaryCases, 0); // the cases on patch boundaries exercise it
}

// The traversal's shaft index (linespace/shaft_index_fast.glsl) is the same function, bit for bit.
TEST_F(GlTest, FastShaftIndexGlslMatchesCppTwin) { checkShaftIndexTwin({{"CHCRT_LS_TWIN_FAST", ""}}); }

// The texture-buffer lookups of shaders/linespace/linespace_lookup.glsl against the C++ pools of a built set.
TEST_F(GlTest, LineSpaceLookupGlslMatchesCpp) {
    const Bvh bvh = buildBvh(test::makeScene(test::randomSoup(3000, 31)));
    ls::LineSpaceParams params;
    params.n = 4;
    params.depth = 4;
    const ls::LineSpaces spaces = ls::buildLineSpaces(bvh, params);
    const std::vector<gpu::LineSpaceNodeGpu> nodes = spaces.gpuNodes(bvh);
    test::Rng rng{77};
    std::vector<glm::vec4> texels;
    std::vector<glm::uvec2> expected;
    for (int i = 0; i < kCases; ++i) {
        const uint32_t space = rng.below(static_cast<uint32_t>(nodes.size()));
        const Aabb box{nodes[space].boundsMin, nodes[space].boundsMax};
        const vec3 size = box.extent();
        const vec3 origin = rng.uniform3(box.lower - size, box.upper + size);
        const vec3 direction = rng.uniform3(box.lower, box.upper) - origin;
        texels.emplace_back(origin, bitsToFloat(space));
        texels.emplace_back(direction, 0.0f);
        const uint32_t symmetric = ls::shaftIndexForRay(box, params.n, true, origin, direction);
        const uint32_t shaft = ls::shaftIndexForRay(box, params.n, false, origin, direction);
        expected.emplace_back(symmetric != CHCRT_LS_NO_SHAFT && spaces.binaryFilled(space, symmetric) ? 1u : 0u,
                              shaft == CHCRT_LS_NO_SHAFT ? CHCRT_LS_EMPTY_SLOT : spaces.candidates.lookup(space, shaft));
    }
    TextureBuffer input = createTextureBuffer(texels.data(), texels.size() * sizeof(glm::vec4), GL_RGBA32F);
    TextureBuffer nodeBuffer = createTextureBuffer(nodes.data(), nodes.size() * sizeof(nodes[0]), GL_RGBA32F);
    auto uintBuffer = [](const std::vector<uint32_t>& v) {
        return createTextureBuffer(v.data(), v.size() * sizeof(uint32_t), GL_R32UI);
    };
    TextureBuffer binary = uintBuffer(spaces.binaryWords);
    TextureBuffer words = uintBuffer(spaces.candidates.words());
    TextureBuffer offsets = uintBuffer(spaces.candidates.offsets());
    TextureBuffer data = uintBuffer(spaces.candidates.data());
    GlTexture output = createTexture2D(kWidth, kHeight, GL_RGBA32UI);
    const GLuint target = output.id();
    GlFramebuffer framebuffer = createFramebuffer(&target, 1);
    ShaderProgram program({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                           {GL_FRAGMENT_SHADER, "linespace/linespace_lookup_twin.frag.glsl"}},
                          {{"LS_N", std::to_string(params.n)}});
    program.set("width", kWidth);
    program.set("caseCount", kCases);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, kWidth, kHeight);
    program.use();
    glBindTextureUnit(0, input.texture.id());
    glBindTextureUnit(1, nodeBuffer.texture.id());
    glBindTextureUnit(2, binary.texture.id());
    glBindTextureUnit(3, words.texture.id());
    glBindTextureUnit(4, offsets.texture.id());
    glBindTextureUnit(5, data.texture.id());
    drawFullscreenTriangle();
    checkGlErrors("lookup twin draw");
    const std::vector<glm::uvec4> gpu = readTextureRgba32ui(output.id(), kWidth, kHeight);
    int filled = 0, withCandidate = 0, mismatches = 0, tolerated = 0;
    for (int i = 0; i < kCases; ++i) {
        const glm::uvec2 g(gpu[static_cast<size_t>(i)]);
        filled += expected[static_cast<size_t>(i)].x != 0u ? 1 : 0;
        withCandidate += expected[static_cast<size_t>(i)].y != CHCRT_LS_EMPTY_SLOT ? 1 : 0;
        if (g == expected[static_cast<size_t>(i)]) continue;
        // Up to GLSL's division bound (kUlps): the lookups of the shafts the C++ classification gives for a
        // direction (hence inverse direction) and box moved by a few float steps.
        const uint32_t space = floatBitsToUint(texels[size_t(i) * 2].w);
        const vec3 origin(texels[size_t(i) * 2]), direction(texels[size_t(i) * 2 + 1]);
        const auto lookup = [&](const vec3& dir, const vec3& lo, const vec3& hi) {
            const Aabb box{lo, hi};
            const uint32_t symmetric = ls::shaftIndexForRay(box, params.n, true, origin, dir);
            const uint32_t shaft = ls::shaftIndexForRay(box, params.n, false, origin, dir);
            return glm::uvec2(symmetric != CHCRT_LS_NO_SHAFT && spaces.binaryFilled(space, symmetric) ? 1u : 0u,
                              shaft == CHCRT_LS_NO_SHAFT ? CHCRT_LS_EMPTY_SLOT : spaces.candidates.lookup(space, shaft));
        };
        if (explainedByDivisionError(g, direction, nodes[space].boundsMin, nodes[space].boundsMax, lookup)) {
            ++tolerated;
            continue;
        }
        if (++mismatches <= 5) {
            ADD_FAILURE() << "case " << i << ": GLSL (" << g.x << ", " << g.y << ") vs C++ ("
                          << expected[static_cast<size_t>(i)].x << ", " << expected[static_cast<size_t>(i)].y << ")";
        }
    }
    std::printf("[ twin     ] %d lookups: %d in filled shafts, %d with a candidate; %d mismatches, %d within GLSL's "
                "division bound\n", kCases, filled, withCandidate, mismatches, tolerated);
    EXPECT_LE(tolerated, kCases / 100);
    EXPECT_GT(filled, kCases / 4);
    EXPECT_LT(filled, kCases * 19 / 20);
    EXPECT_GT(withCandidate, kCases / 4);
    EXPECT_EQ(mismatches, 0);
}

} // namespace
} // namespace chcrt
