#pragma once
/// @file Conversions between OccupancyGrid2 and octomap::OcTree, the map of record.
///
/// Frame: trees are built in the GRID frame (world minus the grid origin), so that cell (i, j)
/// maps to exactly one voxel column whatever origin / resolution is (a world-frame build aligns
/// only when origin / res is an integer). Callers keep the grid origin beside the tree.

#include <octomap/OcTree.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>

#include "coopnav/distance/occupancy_grid.hpp"

namespace coopnav {

/// Throws std::invalid_argument unless an OcTree can hold the grid as gridToOctree builds it:
/// a resolution whose farthest voxel centre is a finite, non-zero float, and at most 2^15 cells
/// (OctoMap's 16-bit keys, half of them below the origin) each way. gridToOctree checks it first;
/// a daemon that needs only the grid checks it too, so every daemon accepts the same maps.
void checkOctreeCanHold(const OccupancyGrid2& grid, int slab_layers = 2);

/// Builds an OcTree of the grid's resolution holding a slab of slab_layers (>= 1) voxel layers,
/// layer k centred at z = (k + 0.5) * res [m] in the grid frame. Occupied / free cells get the
/// clamping log-odds (max / min), unknown cells are left out; the tree is then pruned (pruning
/// needs an even number of layers, so 2 or 4 keep the tree small). Throws std::invalid_argument
/// on an empty grid, slab_layers < 1, or a grid checkOctreeCanHold refuses.
std::unique_ptr<octomap::OcTree> gridToOctree(const OccupancyGrid2& grid, int slab_layers = 2);

/// Projects the leaves of tree whose z extent overlaps [z_min_m, z_max_m] (tree frame, metres)
/// onto a grid of the tree's resolution. A cell is occupied if any overlapping voxel above it is
/// occupied, else free if any is free, else unknown. The grid spans the x-y bounding box of those
/// leaves; frame_origin_m [m] is the world position of the tree frame's origin (the grid origin
/// the tree was built from), so the result's origin is frame_origin_m + (lowest cell) * res.
/// Returns an empty grid when no leaf overlaps the band. Throws std::invalid_argument, before
/// allocating, when the grid would exceed max_cells cells (a few coarse or far-apart leaves span
/// billions of cells), or when the tree's resolution is not a finite number > 0.
OccupancyGrid2 octreeToGrid(const octomap::OcTree& tree, double z_min_m, double z_max_m,
                            const Eigen::Vector2d& frame_origin_m = Eigen::Vector2d::Zero(),
                            std::int64_t max_cells = std::int64_t{1} << 30);

}  // namespace coopnav
