// generateProceduralScene: dispatch to the generators and fill in the scene's bookkeeping.
#include "renderer/scene/procedural/procedural.h"

#include "renderer/scene/procedural/procedural_internal.h"

namespace chcrt {

Scene generateProceduralScene(const ProceduralSpec& spec, Progress& progress) {
    Scene scene;
    const bool budgeted = spec.kind == ProceduralKind::City || spec.kind == ProceduralKind::Interior ||
                          spec.kind == ProceduralKind::Plant;
    progress.begin("Generating " + toString(spec), budgeted ? spec.targetTriangles : 0);
    procedural::MeshBuilder builder(scene, progress);
    switch (spec.kind) {
    case ProceduralKind::City: procedural::generateCity(spec, builder); break;
    case ProceduralKind::Interior: procedural::generateInterior(spec, builder); break;
    case ProceduralKind::Plant: procedural::generatePlant(spec, builder); break;
    default: procedural::generateAnalytic(spec, builder); break;
    }
    scene.name = toString(spec);
    // One flattened mesh, no instancing: unique = instanced.
    scene.stats.uniqueTriangles = scene.triangles.size();
    scene.stats.instancedTriangles = scene.triangles.size();
    scene.stats.meshCount = 1;
    scene.stats.instanceCount = 1;
    progress.end();
    return scene;
}

} // namespace chcrt
