#include "renderer/render/frame_targets.h"

namespace chcrt {
namespace {

void makeRayTextures(RayTextures& rays, int width, int height) {
    rays.origin = createTexture2D(width, height, GL_RGBA32F);
    rays.direction = createTexture2D(width, height, GL_RGBA32F);
    rays.active = createTexture2D(width, height, GL_DEPTH_COMPONENT16);
    const GLuint colors[2] = {rays.origin.id(), rays.direction.id()};
    rays.framebuffer = createFramebuffer(colors, 2, rays.active.id());
}

void makeHitTargets(HitTargets& hits, int width, int height) {
    hits.hit = createTexture2D(width, height, GL_RGBA32UI);
    hits.cost = createTexture2D(width, height, GL_RGBA32UI);
    hits.depth = createTexture2D(width, height, GL_DEPTH_COMPONENT32F);
    const GLuint colors[2] = {hits.hit.id(), hits.cost.id()};
    hits.framebuffer = createFramebuffer(colors, 2, hits.depth.id());
}

GlFramebuffer makeSingleTarget(GlTexture& texture, int width, int height, GLenum format) {
    texture = createTexture2D(width, height, format);
    const GLuint color = texture.id();
    return createFramebuffer(&color, 1);
}

} // namespace

FrameTargets::FrameTargets(int w, int h) : width(w), height(h) {
    gbufferPosition = createTexture2D(w, h, GL_RGBA32F);
    gbufferNormal = createTexture2D(w, h, GL_RGBA32F);
    gbufferAlbedo = createTexture2D(w, h, GL_RGBA16F);
    gbufferTriangle = createTexture2D(w, h, GL_R32UI);
    gbufferDepth = createTexture2D(w, h, GL_DEPTH_COMPONENT32F);
    const GLuint gbufferColors[4] = {gbufferPosition.id(), gbufferNormal.id(), gbufferAlbedo.id(),
                                     gbufferTriangle.id()};
    gbuffer = createFramebuffer(gbufferColors, 4, gbufferDepth.id());
    for (int i = 0; i < 2; ++i) {
        makeRayTextures(rays[i], w, h);
        makeHitTargets(hits[i], w, h);
        const GLuint hitColors[2] = {hits[i].hit.id(), hits[i].cost.id()};
        hits[i].maskedFramebuffer = createFramebuffer(hitColors, 2, rays[i].active.id());
        hits[i].maskedFor = rays[i].active.id();
    }
    accumDirectFbo = makeSingleTarget(accumDirect, w, h, GL_RGBA32F);
    accumAoFbo = makeSingleTarget(accumAo, w, h, GL_RGBA32F);
    accumIndirectFbo = makeSingleTarget(accumIndirect, w, h, GL_RGBA32F);
    outputHdr = createTexture2D(w, h, GL_RGBA32F);
    outputDisplay = createTexture2D(w, h, GL_RGBA32F);
    const GLuint outputs[2] = {outputHdr.id(), outputDisplay.id()};
    output = createFramebuffer(outputs, 2);
}

} // namespace chcrt
