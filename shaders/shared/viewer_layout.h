#ifndef CHCRT_SHARED_VIEWER_LAYOUT_H
#define CHCRT_SHARED_VIEWER_LAYOUT_H
// Texture units and mode numbers of the viewer's display passes (app/viewer/view_display.cpp), shared by the
// C++ side and shaders/viewer/*.glsl. G-buffer channels use the renderer's units (shared/render_layout.h).
#define CHCRT_VIEWER_UNIT_DISPLAY 0     // sampler2D RGBA32F: the renderer's tone-mapped frame (linear display values)
#define CHCRT_VIEWER_UNIT_ACCUM 1       // sampler2D RGBA32F: sum of HDR frames (rgb), frame count (a)
#define CHCRT_VIEWER_UNIT_COST 2        // usampler2D RGBA32UI: inner nodes, leaves, triangles, capped
#define CHCRT_VIEWER_UNIT_SOURCE 3      // sampler2D: the texture a copy/blit pass reads
#define CHCRT_VIEWER_UNIT_CULLING_COST 4 // usampler2D R32UI: CHC+RT's cost debug image (steps, bit 31 capped)

// View modes: the order of app::ViewMode (view_modes.h), checked by a static_assert there.
#define CHCRT_VIEW_SHADED 0
#define CHCRT_VIEW_POSITION 1
#define CHCRT_VIEW_NORMAL 2
#define CHCRT_VIEW_ALBEDO 3
#define CHCRT_VIEW_TRIANGLE 4
#define CHCRT_VIEW_DEPTH 5
#define CHCRT_VIEW_COST 6
#endif
