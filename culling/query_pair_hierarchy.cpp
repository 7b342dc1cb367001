#include "culling/query_pair_hierarchy.h"

namespace chcrt {

bool preferObjectSplit(float nodeArea, float rootArea, int64_t tileArea, int64_t screenArea, float tq) {
    const double objectRatio = rootArea > 0.0f ? double(nodeArea) / rootArea : 0.0;
    const double screenRatio = screenArea > 0 ? double(tileArea) / double(screenArea) : 0.0;
    return objectRatio > double(tq) * screenRatio;
}

PairSplit decideSplit(const Tile& tile, uint32_t node, const SubtreePartition& partition, int screenWidth,
                      int screenHeight, const QueryPairOptions& options) {
    const bool screenSplittable = tile.width > options.minTileSize || tile.height > options.minTileSize;
    const bool objectSplittable = !partition.isRoot(node);
    if (!screenSplittable && !objectSplittable) return PairSplit::None;
    if (!screenSplittable) return PairSplit::Object;
    if (!objectSplittable) return PairSplit::Screen;
    return preferObjectSplit(partition.surfaceArea(node), partition.surfaceArea(0), tile.area(),
                             int64_t(screenWidth) * screenHeight, options.tq)
               ? PairSplit::Object
               : PairSplit::Screen;
}

PairSplit decideSplit(const Tile& tile, uint32_t node, const CullingHierarchy& hierarchy, int screenWidth,
                      int screenHeight, const QueryPairOptions& options) {
    const bool screenSplittable = tile.width > options.minTileSize || tile.height > options.minTileSize;
    const bool objectSplittable = !hierarchy.nodes[node].isTerminal();
    if (!screenSplittable && !objectSplittable) return PairSplit::None;
    if (!screenSplittable) return PairSplit::Object;
    if (!objectSplittable) return PairSplit::Screen;
    return preferObjectSplit(hierarchy.surfaceArea(node), hierarchy.surfaceArea(0), tile.area(),
                             int64_t(screenWidth) * screenHeight, options.tq)
               ? PairSplit::Object
               : PairSplit::Screen;
}

int splitTile(const Tile& tile, int minTileSize, std::array<Tile, 4>& children) {
    const bool splitX = tile.width > minTileSize && tile.width >= 2;
    const bool splitY = tile.height > minTileSize && tile.height >= 2;
    const int w0 = splitX ? tile.width / 2 : tile.width;
    const int h0 = splitY ? tile.height / 2 : tile.height;
    int count = 0;
    for (int j = 0; j < (splitY ? 2 : 1); ++j) {
        for (int i = 0; i < (splitX ? 2 : 1); ++i) {
            Tile c;
            c.x = tile.x + i * w0;
            c.y = tile.y + j * h0;
            c.width = i == 0 ? w0 : tile.width - w0;
            c.height = j == 0 ? h0 : tile.height - h0;
            children[size_t(count++)] = c;
        }
    }
    return count;
}

} // namespace chcrt
