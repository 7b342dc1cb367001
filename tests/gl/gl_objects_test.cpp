// GL object helpers: fullscreen passes into float targets, texture buffers, framebuffers, queries, handles.
#include "renderer/core/error.h"
#include "renderer/core/timing.h"
#include "renderer/gl/gl_object_count.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "tests/gl/gl_test_fixture.h"

#include <chrono>
#include <cstring>
#include <random>

namespace chcrt {
namespace {

using test::GlTest;

struct Target {
    GlTexture texture;
    GlFramebuffer framebuffer;
};

Target makeTarget(int width, int height) {
    Target target;
    target.texture = createTexture2D(width, height, GL_RGBA32F);
    const GLuint colour = target.texture.id();
    target.framebuffer = createFramebuffer(&colour, 1);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(target.framebuffer.id(), GL_COLOR, 0, zero);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer.id());
    glViewport(0, 0, width, height);
    return target;
}

ShaderProgram fullscreenProgram(const std::string& fragment, const std::vector<ShaderDefine>& defines = {}) {
    return ShaderProgram({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"}, {GL_FRAGMENT_SHADER, fragment}},
                         defines);
}

TEST_F(GlTest, FullscreenPassWritesExactColourIntoEveryPixel) {
    // Odd sizes: a quad's diagonal or an off-by-one viewport would leave a row, a column or a seam unwritten.
    constexpr int kWidth = 61, kHeight = 47;
    Target target = makeTarget(kWidth, kHeight);
    ShaderProgram program = fullscreenProgram("test/solid_colour.frag.glsl");
    // Values an 8-bit or clamped target could not hold; 0.1f checks that no conversion touches the bits.
    const glm::vec4 colour(0.1f, -2.5f, 1.0e20f, 3.0f);
    program.set("colour", colour);
    program.use();
    drawFullscreenTriangle();
    checkGlErrors("fullscreen draw");
    const std::vector<glm::vec4> texels = test::readTextureRgba32f(target.texture.id(), kWidth, kHeight);
    int wrong = 0;
    for (const glm::vec4& texel : texels) {
        wrong += texel != colour ? 1 : 0;
    }
    EXPECT_EQ(wrong, 0) << "first texel " << texels[0].x << " " << texels[0].y << " " << texels[0].z;
}

TEST_F(GlTest, ShaderDefinesReachTheCompiler) {
    Target target = makeTarget(8, 8);
    ShaderProgram program = fullscreenProgram("test/define_colour.frag.glsl",
                                              {{"RED", "0.25f"}, {"GREEN", "0.5f"}, {"USE_BLUE", ""}});
    program.use();
    drawFullscreenTriangle();
    for (const glm::vec4& texel : test::readTextureRgba32f(target.texture.id(), 8, 8)) {
        ASSERT_EQ(texel, glm::vec4(0.25f, 0.5f, 1.0f, 1.0f));
    }
}

TEST_F(GlTest, TextureBufferRoundTripIsBitExact) {
    constexpr int kWidth = 32, kHeight = 32, kTexels = 1000; // the last 24 pixels read past the end
    std::mt19937 rng(7);
    std::vector<glm::vec4> data(kTexels);
    for (glm::vec4& texel : data) {
        for (int c = 0; c < 4; ++c) {
            // Arbitrary finite normal floats of all magnitudes and both signs: random exponents and mantissas.
            const uint32_t bits = (rng() & 0x807FFFFFu) | ((1u + rng() % 253u) << 23);
            std::memcpy(&texel[c], &bits, sizeof(float));
        }
    }
    TextureBuffer tbo = createTextureBuffer(data.data(), data.size() * sizeof(glm::vec4), GL_RGBA32F);
    EXPECT_EQ(tbo.bytes, data.size() * sizeof(glm::vec4));
    Target target = makeTarget(kWidth, kHeight);
    ShaderProgram program = fullscreenProgram("test/texture_buffer_copy.frag.glsl");
    program.set("width", kWidth);
    program.set("texelCount", kTexels);
    program.use();
    glBindTextureUnit(0, tbo.texture.id());
    drawFullscreenTriangle();
    const std::vector<glm::vec4> result = test::readTextureRgba32f(target.texture.id(), kWidth, kHeight);
    for (int i = 0; i < kWidth * kHeight; ++i) {
        const glm::vec4 expected = i < kTexels ? data[static_cast<size_t>(i)] : glm::vec4(-1.0f);
        ASSERT_EQ(std::memcmp(&result[static_cast<size_t>(i)], &expected, sizeof(glm::vec4)), 0) << "texel " << i;
    }
}

TEST_F(GlTest, TextureBufferRejectsOversizeAndUnknownFormats) {
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    // The limit is checked before allocating, so no data (and no memory) is needed for the oversized request.
    const size_t tooLarge = (static_cast<size_t>(maxTexels) + 1) * 16;
    EXPECT_THROW(createTextureBuffer(nullptr, tooLarge, GL_RGBA32F), GlError);
    EXPECT_THROW(createTextureBuffer(nullptr, 64, GL_DEPTH_COMPONENT32F), GlError);
    // An empty buffer is valid (empty scenes) and reads as zero.
    EXPECT_NO_THROW(createTextureBuffer(nullptr, 0, GL_RGBA32F));
}

TEST_F(GlTest, OcclusionQueryCountsScissoredFragmentsExactly) {
    Target target = makeTarget(64, 64);
    ShaderProgram solid = fullscreenProgram("test/solid_colour.frag.glsl");
    ShaderProgram checker = fullscreenProgram("test/checker_discard.frag.glsl");
    constexpr int kX = 5, kY = 7, kW = 37, kH = 23;
    glEnable(GL_SCISSOR_TEST);
    glScissor(kX, kY, kW, kH);

    auto countSamples = [](const ShaderProgram& program) {
        GlQuery query = createQuery(GL_SAMPLES_PASSED);
        program.use();
        glBeginQuery(GL_SAMPLES_PASSED, query.id());
        drawFullscreenTriangle();
        glEndQuery(GL_SAMPLES_PASSED);
        GLuint64 samples = 0;
        glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &samples);
        return samples;
    };
    EXPECT_EQ(countSamples(solid), static_cast<GLuint64>(kW * kH)); // 851
    GLuint64 evenPixels = 0;
    for (int y = kY; y < kY + kH; ++y) {
        for (int x = kX; x < kX + kW; ++x) {
            evenPixels += (x + y) % 2 == 0 ? 1 : 0;
        }
    }
    EXPECT_EQ(countSamples(checker), evenPixels); // 426: discarded fragments do not count

    // Nothing inside an empty scissor: the boolean query says so.
    glScissor(0, 0, 0, 0);
    GlQuery any = createQuery(GL_ANY_SAMPLES_PASSED);
    solid.use();
    glBeginQuery(GL_ANY_SAMPLES_PASSED, any.id());
    drawFullscreenTriangle();
    glEndQuery(GL_ANY_SAMPLES_PASSED);
    GLuint anyPassed = 1;
    glGetQueryObjectuiv(any.id(), GL_QUERY_RESULT, &anyPassed);
    EXPECT_EQ(anyPassed, 0u);
    glDisable(GL_SCISSOR_TEST);
}

TEST_F(GlTest, FramebufferWithMultipleTargetsAndDepth) {
    GlTexture a = createTexture2D(16, 16, GL_RGBA32F);
    GlTexture b = createTexture2D(16, 16, GL_R32UI);
    GlTexture depth = createTexture2D(16, 16, GL_DEPTH_COMPONENT32F);
    const GLuint colours[2] = {a.id(), b.id()};
    GlFramebuffer framebuffer = createFramebuffer(colours, 2, depth.id());
    GLint drawBuffer1 = 0;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer.id());
    glGetIntegerv(GL_DRAW_BUFFER1, &drawBuffer1);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    EXPECT_EQ(drawBuffer1, GL_COLOR_ATTACHMENT1);
    GlTexture depthStencil = createTexture2D(16, 16, GL_DEPTH24_STENCIL8);
    EXPECT_NO_THROW(createFramebuffer(colours, 1, depthStencil.id()));
    EXPECT_NO_THROW(createFramebuffer(nullptr, 0, depth.id())); // depth-only pass
}

TEST_F(GlTest, IncompleteFramebufferThrows) {
    // A depth format is not colour-renderable: GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT.
    GlTexture depth = createTexture2D(16, 16, GL_DEPTH_COMPONENT32F);
    const GLuint colour = depth.id();
    try {
        createFramebuffer(&colour, 1);
        FAIL() << "no GlError";
    } catch (const GlError& e) {
        EXPECT_NE(std::string(e.what()).find("INCOMPLETE"), std::string::npos) << e.what();
    }
}

TEST_F(GlTest, HandlesMoveAndDeleteTheirObject) {
    GlBuffer buffer = createBuffer(64, nullptr);
    const GLuint id = buffer.id();
    EXPECT_EQ(glIsBuffer(id), GL_TRUE);
    GlBuffer moved = std::move(buffer);
    EXPECT_FALSE(buffer); // NOLINT(bugprone-use-after-move): the moved-from state is what is tested
    EXPECT_EQ(moved.id(), id);
    moved = GlBuffer();
    EXPECT_EQ(glIsBuffer(id), GL_FALSE);
    GlVertexArray vao = createVertexArray();
    EXPECT_EQ(glIsVertexArray(vao.id()), GL_TRUE);
}

// The timer measures the GPU work between its begin() and end() in milliseconds: more than nothing for real work,
// never more than the wall time around it (a wrong unit, the result is in nanoseconds, exceeds it by 1000x or more),
// and an interval without work after it reads less (a timer that kept counting from an earlier query, or from its
// creation, would not). No lower bound relative to the wall time: llvmpipe's elapsed time covers only part of the
// rasterisation (0.4 to 300 ms for these same draws, 30 to 300 ms of wall time, on a loaded machine).
TEST_F(GlTest, GpuTimerMeasuresTheDrawsBetweenBeginAndEnd) {
    Target target = makeTarget(1024, 1024);
    ShaderProgram program = fullscreenProgram("test/solid_colour.frag.glsl");
    program.set("colour", glm::vec4(0.5f));
    program.use();
    glFinish();
    GpuTimer timer;
    const auto start = std::chrono::steady_clock::now();
    timer.begin();
    for (int i = 0; i < 16; ++i) drawFullscreenTriangle();
    timer.end();
    const double ms = timer.milliseconds();
    const double wallMs = millisecondsSince(start);
    EXPECT_GT(ms, 0.0);
    EXPECT_LE(ms, wallMs) << "GPU " << ms << " ms, wall " << wallMs << " ms";
    GpuTimer idle;
    idle.begin();
    idle.end();
    const double idleMs = idle.milliseconds();
    EXPECT_GE(idleMs, 0.0);
    EXPECT_LT(idleMs, ms);
    checkGlErrors("timer");
}

// The live-object counts (gl_object_count.h) follow every creation and deletion made through the function table:
// RAII owners, raw glCreate*/glGen* calls (as the CHC+RT query pool makes them), programs and shaders, syncs.
TEST_F(GlTest, LiveObjectCountsFollowCreationAndDeletion) {
    const GlObjectCounts before = liveGlObjects();
    {
        TextureBuffer tbo = createTextureBuffer(nullptr, 64, GL_RGBA32F); // a buffer and a texture
        GlTexture texture = createTexture2D(4, 4, GL_RGBA8);
        const GLuint colour = texture.id();
        GlFramebuffer fbo = createFramebuffer(&colour, 1);
        GlQuery query = createQuery(GL_SAMPLES_PASSED);
        GlVertexArray vao = createVertexArray();
        GLuint raw[3] = {};
        glCreateQueries(GL_SAMPLES_PASSED, 3, raw);
        GLuint sampler = 0;
        glGenSamplers(1, &sampler);
        const GLsync sync = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
        const GlObjectCounts during = liveGlObjects();
        EXPECT_EQ(during.buffers - before.buffers, 1);
        EXPECT_EQ(during.textures - before.textures, 2);
        EXPECT_EQ(during.framebuffers - before.framebuffers, 1);
        EXPECT_EQ(during.queries - before.queries, 4);
        EXPECT_EQ(during.vertexArrays - before.vertexArrays, 1);
        EXPECT_EQ(during.samplers - before.samplers, 1);
        EXPECT_EQ(during.syncs - before.syncs, 1);
        EXPECT_EQ(during.total() - before.total(), 11);
        glDeleteQueries(3, raw);
        glDeleteSamplers(1, &sampler);
        glDeleteSync(sync);
        const GLuint none = 0;
        glDeleteBuffers(1, &none); // name 0 is ignored by GL and by the count
        EXPECT_EQ(liveGlObjects().total() - before.total(), 6);
        checkGlErrors("counted objects");
    }
    {
        ShaderProgram program({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                               {GL_FRAGMENT_SHADER, "test/solid_colour.frag.glsl"}});
        EXPECT_EQ(liveGlObjects().programs - before.programs, 1);
    }
    const GlObjectCounts after = liveGlObjects();
    EXPECT_EQ(after.named(), before.named()); // every kind back where it was
    EXPECT_EQ(after.shaders, before.shaders); // the program's shaders were deleted once linked
}

} // namespace
} // namespace chcrt
