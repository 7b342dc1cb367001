// generateProceduralScene: dispatch to the generators and fill in the scene's bookkeeping.
#include "renderer/scene/procedural/procedural.h"

#include "renderer/scene/procedural/procedural_internal.h"

namespace chcrt {

Scene generateProceduralScene(const ProceduralSpec& spec) {
    Scene scene;
    procedural::MeshBuilder builder(scene);
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
    return scene;
}

} // namespace chcrt
