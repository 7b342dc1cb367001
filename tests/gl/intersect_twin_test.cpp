// Twin test of shaders/shared/intersect.h: the GLSL build (shaders/test/intersect_twin.frag.glsl, one case per
// pixel) against the C++ build of the same text, over seeded random rays, boxes and triangles.
#include "renderer/core/error.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "shaders/shared/intersect.h"
#include "tests/gl/gl_test_fixture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace chcrt {
namespace {

using glm::vec3;
using test::GlTest;

constexpr int kTexelsPerCase = 8; // origin, direction, invDir, boxMin, boxMax, v0, v1, v2
constexpr int kWidth = 128, kHeight = 64, kCases = kWidth * kHeight;

struct Case {
    vec3 origin, direction, invDir, boxMin, boxMax, v0, v1, v2;
};

// Small deterministic generator (std distributions differ between standard libraries).
struct Rng {
    uint64_t state;
    uint32_t next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<uint32_t>(state >> 33);
    }
    float uniform(float lo, float hi) { return lo + (hi - lo) * static_cast<float>(next() >> 8) * 0x1p-24f; }
    vec3 uniform3(float lo, float hi) { return vec3(uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)); }
};

std::vector<Case> makeCases() {
    Rng rng{12345};
    std::vector<Case> cases;
    while (static_cast<int>(cases.size()) < kCases) {
        const int i = static_cast<int>(cases.size());
        Case c;
        c.v0 = rng.uniform3(-1.0f, 1.0f);
        c.v1 = rng.uniform3(-1.0f, 1.0f);
        c.v2 = rng.uniform3(-1.0f, 1.0f);
        if (i % 50 == 0) {
            // Parallel ray: triangle in a z plane, direction with z = 0 gives det == 0 exactly on any hardware.
            c.v1.z = c.v0.z;
            c.v2.z = c.v0.z;
        }
        c.origin = rng.uniform3(-4.0f, 4.0f);
        // Aim at a point of the triangle's plane with barycentrics in [-0.25, 1.25]: about half the rays hit.
        float b1 = rng.uniform(-0.25f, 1.25f), b2 = rng.uniform(-0.25f, 1.25f);
        if (i % 16 == 3) {
            b2 = 0.0f; // on the edge v0-v1 (up to rounding): where the two builds may decide differently
        } else if (i % 16 == 5) {
            b1 = rng.uniform(0.0f, 1.0f);
            b2 = 1.0f - b1; // on the edge v1-v2
        } else if (i % 16 == 7) {
            b1 = b2 = 0.0f; // at the vertex v0
        }
        const vec3 target = c.v0 + b1 * (c.v1 - c.v0) + b2 * (c.v2 - c.v0);
        c.direction = target - c.origin;
        if (i % 50 == 0) {
            c.direction.z = 0.0f;
        } else if (i % 8 == 1) {
            c.direction.x = 0.0f; // axis-parallel component: invDir = +-inf in the slab test
        } else if (i % 8 == 2) {
            c.direction.y = -0.0f;
            c.direction.z = 0.0f;
        }
        c.invDir = 1.0f / c.direction;
        // Boxes: half are the triangle's bounds with a random margin, half anywhere.
        if (i % 2 == 0) {
            c.boxMin = glm::min(glm::min(c.v0, c.v1), c.v2) - rng.uniform3(0.0f, 0.2f);
            c.boxMax = glm::max(glm::max(c.v0, c.v1), c.v2) + rng.uniform3(0.0f, 0.2f);
        } else {
            const vec3 centre = rng.uniform3(-1.5f, 1.5f), half = rng.uniform3(0.05f, 1.0f);
            c.boxMin = centre - half;
            c.boxMax = centre + half;
        }
        // (bound - origin) * inf must not be 0 * inf (NaN; intersect.h's documented precondition).
        bool valid = c.direction != vec3(0.0f);
        for (int a = 0; a < 3; ++a) {
            valid = valid && c.boxMin[a] != c.origin[a] && c.boxMax[a] != c.origin[a];
        }
        if (valid) {
            cases.push_back(c);
        }
    }
    return cases;
}

// Distance in units in the last place between two finite floats (0 for +0 and -0).
int64_t ulpDistance(float a, float b) {
    auto ordered = [](float f) {
        int32_t i;
        std::memcpy(&i, &f, sizeof(i));
        return i < 0 ? static_cast<int64_t>(INT32_MIN) - i : static_cast<int64_t>(i);
    };
    return std::llabs(ordered(a) - ordered(b));
}

// Signed distance (in barycentric units) of the ray's hit point from the nearest triangle edge, computed in
// double precision: positive inside. Decides which cases are "near an edge" independently of float rounding.
double edgeMargin(const Case& c) {
    using glm::dvec3;
    const dvec3 o(c.origin), d(c.direction), v0(c.v0), e1 = dvec3(c.v1) - v0, e2 = dvec3(c.v2) - v0;
    const dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) {
        return -1.0;
    }
    const dvec3 s = o - v0, q = glm::cross(s, e1);
    const double u = glm::dot(s, p) / det, v = glm::dot(d, q) / det;
    return std::min({u, 1.0 - u, v, 1.0 - u - v});
}

// Forward error bound of intersectRayTriangle's (t, u, v) for *any* evaluation order of its dot and cross
// products, with or without fused multiply-adds (Higham, "Accuracy and Stability of Numerical Algorithms",
// §3.1: |fl(a.b) - a.b| <= gamma_n sum|a_i b_i|, gamma_n = n u / (1 - n u), u = 2^-24). e1, e2 and s are single
// subtractions, identical in both builds; p = cross(d, e2) and q = cross(s, e1) carry gamma_2 per component,
// the dot products over them gamma_3 more, so num = dot(x, p) is within gamma_6 sum|x_i| P_i, where P is the
// cross product of the absolute values. Dividing by det adds its relative error; the reciprocal and the final
// multiply add a few u (GLSL allows 2.5 ulp for division, so 4 u are budgeted). Both builds satisfy the bound,
// so they differ by at most twice it.
struct TriangleErrorBound {
    double t, u, v;
};
TriangleErrorBound triangleErrorBound(const Case& c, const vec3& result) {
    using glm::dvec3;
    const dvec3 d = glm::abs(dvec3(c.direction));
    const dvec3 e1 = glm::abs(dvec3(c.v1 - c.v0)), e2 = glm::abs(dvec3(c.v2 - c.v0));
    const dvec3 s = glm::abs(dvec3(c.origin - c.v0));
    auto absCross = [](const dvec3& a, const dvec3& b) {
        return dvec3(a.y * b.z + a.z * b.y, a.z * b.x + a.x * b.z, a.x * b.y + a.y * b.x);
    };
    const dvec3 p = absCross(d, e2), q = absCross(s, e1);
    const double unit = 0x1p-24, gamma6 = 6 * unit / (1 - 6 * unit);
    const vec3 e1f = c.v1 - c.v0;
    const double det = std::abs(static_cast<double>(glm::dot(e1f, glm::cross(c.direction, c.v2 - c.v0))));
    const double detError = gamma6 * glm::dot(e1, p);
    auto bound = [&](double numError, double value) {
        return 2.0 * ((numError + std::abs(value) * detError) / det + 4 * unit * std::abs(value));
    };
    return {bound(gamma6 * glm::dot(e2, q), result.x), bound(gamma6 * glm::dot(s, p), result.y),
            bound(gamma6 * glm::dot(d, q), result.z)};
}

TEST_F(GlTest, IntersectGlslMatchesCppTwin) {
    const std::vector<Case> cases = makeCases();
    static_assert(sizeof(Case) == 8 * sizeof(vec3));
    // Pack as RGBA32F texels (xyz + unused w).
    std::vector<glm::vec4> texels;
    for (const Case& c : cases) {
        for (const vec3& v : {c.origin, c.direction, c.invDir, c.boxMin, c.boxMax, c.v0, c.v1, c.v2}) {
            texels.emplace_back(v, 0.0f);
        }
    }
    TextureBuffer input = createTextureBuffer(texels.data(), texels.size() * sizeof(glm::vec4), GL_RGBA32F);
    GlTexture boxOut = createTexture2D(kWidth, kHeight, GL_RGBA32F);
    GlTexture triangleOut = createTexture2D(kWidth, kHeight, GL_RGBA32F);
    const GLuint targets[2] = {boxOut.id(), triangleOut.id()};
    GlFramebuffer framebuffer = createFramebuffer(targets, 2);
    ShaderProgram program({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                           {GL_FRAGMENT_SHADER, "test/intersect_twin.frag.glsl"}},
                          {{"TWIN_TEXELS_PER_CASE", std::to_string(kTexelsPerCase)}});
    program.set("width", kWidth);
    program.set("caseCount", kCases);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, kWidth, kHeight);
    program.use();
    glBindTextureUnit(0, input.texture.id());
    drawFullscreenTriangle();
    checkGlErrors("twin draw");
    const std::vector<glm::vec4> gpuBox = test::readTextureRgba32f(boxOut.id(), kWidth, kHeight);
    const std::vector<glm::vec4> gpuTriangle = test::readTextureRgba32f(triangleOut.id(), kWidth, kHeight);

    int boxHits = 0, boxMismatches = 0;
    int triangleHits = 0, bothHit = 0, exactTriangles = 0, decisionMismatches = 0, nearEdge = 0;
    int outsideBound = 0, decisionMismatchesAwayFromEdges = 0;
    std::vector<int64_t> ulpT, ulpUv;
    double worstBoundRatio = 0.0;
    for (int i = 0; i < kCases; ++i) {
        const Case& c = cases[static_cast<size_t>(i)];
        // Ray/box: subtract, multiply, min, max. Each is a single correctly rounded IEEE operation with nothing
        // to reorder or fuse, so the GPU must reproduce the C++ bits exactly.
        const glm::vec2 box = gpu::intersectRayAabb(c.origin, c.invDir, c.boxMin, c.boxMax);
        const bool boxHit = gpu::rayHitsAabb(box, 0.0f, 3.402823466e+38f);
        const glm::vec4& g = gpuBox[static_cast<size_t>(i)];
        boxHits += boxHit ? 1 : 0;
        if (g.x != box.x || g.y != box.y || (g.z == 1.0f) != boxHit) {
            if (++boxMismatches <= 5) {
                ADD_FAILURE() << "case " << i << ": box (" << g.x << ", " << g.y << ", " << g.z << ") vs C++ ("
                              << box.x << ", " << box.y << ", " << boxHit << ")";
            }
        }

        // Ray/triangle: dot() has no prescribed summation order and GLSL compilers may contract a * b + c into
        // an fma (unless `precise`), so t, u, v may differ in the last bits; they must stay within the bound.
        const vec3 tri = gpu::intersectRayTriangle(c.origin, c.direction, c.v0, c.v1, c.v2);
        const vec3 h(gpuTriangle[static_cast<size_t>(i)]);
        const bool cpuHit = tri.x != -1.0f, gpuHit = h.x != -1.0f;
        triangleHits += cpuHit ? 1 : 0;
        if (i % 50 == 0) {
            EXPECT_FALSE(cpuHit || gpuHit) << "parallel case " << i; // det == 0 exactly on both
        }
        if (!cpuHit && !gpuHit) {
            EXPECT_EQ(h, tri) << "case " << i; // the miss value (-1, 0, 0) on both sides
            ++exactTriangles;
            continue;
        }
        const TriangleErrorBound bound = triangleErrorBound(c, tri);
        const double margin = edgeMargin(c);
        const bool near = std::abs(margin) <= bound.u + bound.v;
        nearEdge += near ? 1 : 0;
        if (cpuHit != gpuHit) {
            ++decisionMismatches;
            if (!near) {
                ++decisionMismatchesAwayFromEdges;
                ADD_FAILURE() << "case " << i << ": hit decision differs " << margin << " from an edge";
            }
            continue;
        }
        ++bothHit;
        // Ulps are reported for information only, away from edges: near u = 0 a tiny absolute difference is
        // millions of ulps (or crosses zero), which is why the assertion uses the error bound instead.
        const int64_t tUlps = ulpDistance(h.x, tri.x);
        const int64_t uvUlps = std::max(ulpDistance(h.y, tri.y), ulpDistance(h.z, tri.z));
        if (!near) {
            ulpT.push_back(tUlps);
            ulpUv.push_back(uvUlps);
        }
        exactTriangles += tUlps == 0 && uvUlps == 0 ? 1 : 0;
        const double ratio = std::max({std::abs(double(h.x) - tri.x) / bound.t, std::abs(double(h.y) - tri.y) / bound.u,
                                       std::abs(double(h.z) - tri.z) / bound.v});
        worstBoundRatio = std::max(worstBoundRatio, ratio);
        if (ratio > 1.0 && ++outsideBound <= 5) {
            ADD_FAILURE() << "case " << i << ": GLSL (" << h.x << ", " << h.y << ", " << h.z << ") vs C++ (" << tri.x
                          << ", " << tri.y << ", " << tri.z << ") differ by " << ratio << "x the error bound";
        }
    }
    auto percentile = [](std::vector<int64_t> v, double q) {
        std::sort(v.begin(), v.end());
        return v.empty() ? 0ll : static_cast<long long>(v[static_cast<size_t>(q * double(v.size() - 1))]);
    };
    auto fractionExact = [](const std::vector<int64_t>& v) {
        return v.empty() ? 1.0 : double(std::count(v.begin(), v.end(), 0)) / double(v.size());
    };
    std::printf("[ twin     ] %d cases: boxes %d hits, %d mismatches; triangles %d hits, %d/%d bit-exact; hits away "
                "from edges: exact t %.0f%%, uv %.0f%%; ulps t median %lld p99 %lld max %lld, uv median %lld p99 %lld max %lld; "
                "worst |diff|/bound %.3f; decision mismatches %d (%d cases near an edge)\n",
                kCases, boxHits, boxMismatches, triangleHits, exactTriangles, kCases, 100 * fractionExact(ulpT),
                100 * fractionExact(ulpUv), percentile(ulpT, 0.5), percentile(ulpT, 0.99), percentile(ulpT, 1.0),
                percentile(ulpUv, 0.5), percentile(ulpUv, 0.99), percentile(ulpUv, 1.0), worstBoundRatio,
                decisionMismatches, nearEdge);
    // The inputs must exercise both outcomes, or the comparison proves little.
    EXPECT_GT(boxHits, kCases / 5);
    EXPECT_LT(boxHits, kCases * 4 / 5);
    EXPECT_GT(triangleHits, kCases / 5);
    EXPECT_LT(triangleHits, kCases * 4 / 5);
    EXPECT_EQ(boxMismatches, 0);
    EXPECT_EQ(outsideBound, 0);
    EXPECT_EQ(decisionMismatchesAwayFromEdges, 0);
    EXPECT_GT(nearEdge, kCases / 32); // the edge-aimed cases really test the decision near edges
}

} // namespace
} // namespace chcrt
