// The element forest of the hierarchical method (Hanrahan, Salzman & Aupperle 1991): every input
// triangle, pre-split (conforming) into roots of at most 4^kRootLevels output patches, each the top
// of a tree of 1:4 splits down to meshing.max_patch_area; the leaves are the output patches.
//
// Every tree is one contiguous block of `elements`, a parent before its children, so that a pass
// down the hierarchy (push) walks a block forwards and a pass up (pull) walks it backwards.
#pragma once

#include <algorithm>
#include <array>
#include <set>
#include <utility>
#include <vector>

#include "mesh/geometry.h"
#include "solver/radiosity.h"

namespace lambert::hierarchical {

// A root holds at most 4^3 = 64 output patches: the roots are the visibility scene's triangles, and
// a link between two roots then spans at most 64 × 64 leaf pairs.
inline constexpr int kRootLevels = 3;

// Distances between elements are compared with their thresholds, and sizes with each other (which of
// a pair to split), with a margin of 1e-9: a regular mesh has pairs exactly at a threshold (centroids
// 4 radii apart) and congruent elements, where rounding would pick the side, differently at another
// scale or placement of the same scene.
inline constexpr double kTie = 1 + 1e-9;

struct Element {
  Triangle tri;
  Vector3 normal;
  Point3 centre;
  double radius = 0;   // about the centroid
  double area = 0;
  int surface = 0;
  int parent = -1;
  int first_child = -1;  // four children, contiguous; -1 for a leaf
  int leaf = -1;         // index of the unknown (output patch) for a leaf
  int root = -1;         // the root element of its tree
  int input = -1;        // the input triangle its tree was cut from (every surface's, in order)
};

// Barycentric coordinates, in the parent, of child c's vertex n: split4's children are {v0, m01, m20},
// {m01, v1, m12}, {m20, m12, v2}, {m01, m12, m20}. Push-down evaluates the parent's linear field there.
inline constexpr double kChildVertex[4][3][3] = {{{1, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}},
                                                 {{0.5, 0.5, 0}, {0, 1, 0}, {0, 0.5, 0.5}},
                                                 {{0.5, 0, 0.5}, {0, 0.5, 0.5}, {0, 0, 1}},
                                                 {{0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}}};

struct ElementForest {
  std::vector<Element> elements;
  std::vector<int> roots;                       // element index of every root, ascending
  std::vector<char> root_two_sided;             // per root: its input triangle's Surface::two_sided
  std::vector<std::pair<int, int>> root_block;  // [first, end) of each root's tree in `elements`
  std::vector<int> leaves;                      // element of each output patch (unknown)
  // Per element: every leaf below lies inside a closed solid (Hemisphere::Enclosed, e.g. a floor
  // under a crate). Such elements take no links, and wholly enclosed roots are left out of the
  // clusters, so that they neither send nor receive through them. Empty: none known.
  std::vector<char> enclosed;
  // Per element, where some leaf is enclosed (empty: none): the area of its leaves that are not. The
  // enclosed part of an element is hidden from every link (its rays meet back faces), so the flux an
  // element gathers lands on its open part only, and what it sends is its open part's mean radiosity
  // (Hierarchy::apply, pull). Spread over the whole element, the flux on the enclosed part would be
  // absorbed where no patch reports it: in a room with a ceiling panel 1 mm under the ceiling, 8e-4 of
  // the power, every surface's irradiance that much low.
  std::vector<double> open_area;

  bool has_children(int e) const { return elements[e].first_child >= 0; }
  bool is_enclosed(int e) const { return !enclosed.empty() && enclosed[e]; }
  // The weight of child c in its parent p's mean radiosity: its share of p's open area.
  double child_weight(int c, int p) const {
    if (open_area.empty()) return elements[c].area / elements[p].area;
    return open_area[p] > 0 ? open_area[c] / open_area[p] : 0.0;
  }
  // What the irradiance element e gathers (its mean over the element) is on its open part: the
  // element's area over that part's, 0 where all of it is enclosed. At most kMaxOpenSpread: a link's
  // rays (16 where they disagree, stratified over the element) resolve its visible share to about a
  // sixteenth, so where the open part is smaller than that, one ray that reached it would make the
  // open leaves many times brighter than the source could (an element of 256 leaves with one open,
  // in the 70 000-patch furnished room); there the excess is lost.
  static constexpr double kMaxOpenSpread = 16;
  double open_spread(int e) const {
    if (open_area.empty()) return 1.0;
    return open_area[e] > 0 ? std::min(elements[e].area / open_area[e], kMaxOpenSpread) : 0.0;
  }
  // The index of root element `root` in `roots`.
  int root_slot(int root) const;
  // The roots' triangles: the occluders of the visibility scene (the same surfaces as the leaves,
  // fewer triangles).
  std::vector<Triangle> root_triangles() const;
  // The output patches (the leaves), in leaf order.
  std::vector<Patch> leaf_patches() const;
};

// An element's triangle by its exact vertices: the leaves meshing.refine_direct marks for one more
// split, found again when the forest is rebuilt (the same triangles come out).
using TriangleKey = std::array<double, 9>;
TriangleKey triangle_key(const Triangle& t);

// The forest of `scene`: roots of at most 4^kRootLevels × max_area, split breadth-first 1:4 until the
// leaves are no larger than max_area, and once more (down to max_area/16) where `split_further` holds
// a leaf.
ElementForest build_forest(const Scene& scene, double max_area, const std::set<TriangleKey>& split_further);

// Marks the elements whose leaves are all Hemisphere::Enclosed (`enclosed_leaf` per leaf).
void mark_enclosed(ElementForest& forest, const std::vector<char>& enclosed_leaf);

}  // namespace lambert::hierarchical
