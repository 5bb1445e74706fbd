#include "coopnav/distance/octree_conversion.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace coopnav {

void checkOctreeCanHold(const OccupancyGrid2& grid, int slab_layers) {
  if (grid.empty()) throw std::invalid_argument("gridToOctree: empty grid");
  if (slab_layers < 1) throw std::invalid_argument("gridToOctree: slab_layers must be >= 1");
  const double res = grid.resolution_m();
  // OctoMap takes coordinates as floats: a resolution whose farthest voxel centre is not a
  // finite float (a walls map at resolution_m 8.9e53, found by fuzz_map_yaml: undefined
  // behaviour in OcTreeBaseImpl::coordToKeyChecked), or that is 0 as a float (every voxel at
  // the same key: a wrong map, silently), is no map an OcTree can hold.
  // Compared as doubles: converting an out-of-range double to float is itself undefined.
  const int extent_cells = std::max({grid.width(), grid.height(), slab_layers});
  const double far_m = (extent_cells + 0.5) * res;
  if (!(res >= static_cast<double>(std::numeric_limits<float>::min())) ||
      !(far_m < static_cast<double>(std::numeric_limits<float>::max()))) {
    std::ostringstream os;
    os << "gridToOctree: resolution " << res << " m is outside what an OcTree holds (float "
       << "coordinates of " << extent_cells << " cells)";
    throw std::invalid_argument(os.str());
  }
  // Voxel i's key is i + 2^15 (cells start at the grid frame's origin), a 16-bit number.
  constexpr int kMaxCellsPerAxis = 1 << 15;
  if (extent_cells > kMaxCellsPerAxis) {
    std::ostringstream os;
    os << "gridToOctree: grid of " << grid.width() << " x " << grid.height()
       << " cells exceeds the OcTree key range (" << kMaxCellsPerAxis << " cells each way)";
    throw std::invalid_argument(os.str());
  }
}

std::unique_ptr<octomap::OcTree> gridToOctree(const OccupancyGrid2& grid, int slab_layers) {
  checkOctreeCanHold(grid, slab_layers);
  const double res = grid.resolution_m();
  auto tree = std::make_unique<octomap::OcTree>(res);
  // Fixed values rather than updateNode(): the map is given, not observed, so every voxel gets
  // the clamped certainty directly.
  const float occupied_log = tree->getClampingThresMaxLog();
  const float free_log = tree->getClampingThresMinLog();
  for (int j = 0; j < grid.height(); ++j) {
    for (int i = 0; i < grid.width(); ++i) {
      const CellState s = grid.at(i, j);
      if (s == CellState::kUnknown) continue;
      const float value = s == CellState::kOccupied ? occupied_log : free_log;
      for (int k = 0; k < slab_layers; ++k) {
        octomap::OcTreeKey key;
        const octomap::point3d p_tree(static_cast<float>((i + 0.5) * res),
                                      static_cast<float>((j + 0.5) * res),
                                      static_cast<float>((k + 0.5) * res));
        // A backstop only: checkOctreeCanHold refused grids beyond the key range, and a centre's
        // float rounding stays within its key; a wrong key would be a silently wrong map.
        if (!tree->coordToKeyChecked(p_tree, key)) {
          throw std::invalid_argument("gridToOctree: grid exceeds the OcTree key range");
        }
        tree->setNodeValue(key, value, /*lazy_eval=*/true);
      }
    }
  }
  tree->updateInnerOccupancy();
  tree->prune();
  return tree;
}

OccupancyGrid2 octreeToGrid(const octomap::OcTree& tree, double z_min_m, double z_max_m,
                            const Eigen::Vector2d& frame_origin_m, std::int64_t max_cells) {
  const double res = tree.getResolution();
  struct Leaf {
    int i0, j0, size;  // cell range [i0, i0 + size) x [j0, j0 + size) in tree-frame cells
    bool occupied;
  };
  std::vector<Leaf> leaves;
  int min_i = INT_MAX, min_j = INT_MAX, max_i = INT_MIN, max_j = INT_MIN;
  const unsigned max_depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const double half_m = 0.5 * it.getSize();
    const double z_m = it.getZ();
    if (z_m + half_m <= z_min_m || z_m - half_m >= z_max_m) continue;
    // Keys index cells as floor(coord / res) + 2^(depth-1); a coarse leaf's key is its first cell.
    const int size = 1 << (max_depth - it.getDepth());
    const octomap::OcTreeKey key = it.getIndexKey();
    const int centre = 1 << (max_depth - 1);
    Leaf leaf{static_cast<int>(key[0]) - centre, static_cast<int>(key[1]) - centre, size,
              tree.isNodeOccupied(*it)};
    min_i = std::min(min_i, leaf.i0);
    min_j = std::min(min_j, leaf.j0);
    max_i = std::max(max_i, leaf.i0 + size - 1);
    max_j = std::max(max_j, leaf.j0 + size - 1);
    leaves.push_back(leaf);
  }
  if (leaves.empty()) return OccupancyGrid2();
  // Checked here, before the grid and the cell loops below: a tree read from a file may hold a
  // few coarse or far-apart leaves spanning 2^30 cells, and filling them took minutes and GBs
  // (found by fuzz_map_bt).
  const std::int64_t width = std::int64_t{max_i} - min_i + 1;
  const std::int64_t height = std::int64_t{max_j} - min_j + 1;
  if (width * height > max_cells) {
    throw std::invalid_argument("octreeToGrid: the leaves span " + std::to_string(width) + " x " +
                                std::to_string(height) + " cells, more than " +
                                std::to_string(max_cells));
  }
  OccupancyGrid2 grid(max_i - min_i + 1, max_j - min_j + 1, res,
                      frame_origin_m + res * Eigen::Vector2d(min_i, min_j), CellState::kUnknown);
  for (const Leaf& leaf : leaves) {
    for (int j = leaf.j0; j < leaf.j0 + leaf.size; ++j) {
      for (int i = leaf.i0; i < leaf.i0 + leaf.size; ++i) {
        const int gi = i - min_i;
        const int gj = j - min_j;
        if (leaf.occupied) {
          grid.set(gi, gj, CellState::kOccupied);
        } else if (grid.at(gi, gj) == CellState::kUnknown) {
          grid.set(gi, gj, CellState::kFree);
        }
      }
    }
  }
  return grid;
}

}  // namespace coopnav
