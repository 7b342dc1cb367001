#pragma once
// The shader stage a full-screen tracing pass runs in (--shader-stage, app/parameters.cpp): a fragment pass with a
// fragment per ray, or a compute pass with an invocation per ray. Both run the same per-ray code and write the
// same bits (render/trace_ray.glsl); they differ in speed: data-centre GPUs run fragment work on few
// graphics-capable units, llvmpipe runs fragments faster (docs/benchmarks.md, "Fragment or compute tracing").
#include "renderer/gl/context.h"

#include <string>

namespace chcrt {

enum class TraceStage { Fragment, Compute, Auto };

// "fragment" | "compute" | "auto"; throws InputError otherwise.
TraceStage parseTraceStage(const std::string& name);
const char* toString(TraceStage stage);

// The stage of tracers constructed without one (BvhTracer's default, so also the pure passes inside other methods):
// --shader-stage sets it for the process; Auto until then.
void setPreferredTraceStage(TraceStage stage);
TraceStage preferredTraceStage();

// The rule of Auto for a renderer: fragment on software rasterisers (llvmpipe runs the fragment pass faster,
// measured: docs/benchmarks.md, "Fragment or compute tracing"), compute on every other renderer (data-centre GPUs run
// fragment work on few graphics-capable units). CHC+RT's recommended configuration takes its cell passes' stage from
// it too (culling/chcrt_tracer.h, recommendedChcrtOptions).
TraceStage autoTraceStage(const RendererTraits& renderer);

// A concrete stage for `requested` on the current context. Auto: the environment variable CHCRT_SHADER_STAGE
// (fragment | compute; the test suite reruns its tracing tests with compute through it) when set, else
// autoTraceStage(currentRendererTraits()). Throws InputError for a bad CHCRT_SHADER_STAGE.
TraceStage resolveTraceStage(TraceStage requested);

} // namespace chcrt
