#include "solver/hierarchical/elements.h"

#include <algorithm>
#include <cmath>

#include "mesh/mesh_ops.h"
#include "solver/cubature.h"

namespace lambert::hierarchical {
namespace {

Element make_element(const Triangle& t, int surface, int parent, int root, int input) {
  Element e;
  e.tri = t;
  e.area = t.area();
  e.normal = t.normal();
  e.centre = t.centroid();
  e.radius = std::max({distance(e.centre, t.v[0]), distance(e.centre, t.v[1]), distance(e.centre, t.v[2])});
  e.surface = surface;
  e.parent = parent;
  e.root = root;
  e.input = input;
  return e;
}

// The tree below `root`, breadth-first: an element larger than max_area is split, and so is a leaf
// marked in `split_further` while its children stay above max_area/16.
void grow_tree(ElementForest& forest, int root, double max_area, const std::set<TriangleKey>& split_further) {
  std::vector<Element>& elements = forest.elements;
  for (int e = root; e < static_cast<int>(elements.size()); ++e) {
    const Element& el = elements[e];
    if (el.area <= max_area && !(el.area / 4 >= max_area / 16 && split_further.count(triangle_key(el.tri)) > 0))
      continue;
    const auto children = split4(el.tri);
    elements[e].first_child = static_cast<int>(elements.size());
    const int surface = elements[e].surface, input = elements[e].input;
    for (const Triangle& c : children) elements.push_back(make_element(c, surface, e, root, input));
  }
}

}  // namespace

TriangleKey triangle_key(const Triangle& t) {
  return {t.v[0].x, t.v[0].y, t.v[0].z, t.v[1].x, t.v[1].y, t.v[1].z, t.v[2].x, t.v[2].y, t.v[2].z};
}

ElementForest build_forest(const Scene& scene, double max_area, const std::set<TriangleKey>& split_further) {
  ElementForest forest;
  const double root_area = max_area * std::pow(4.0, kRootLevels);
  for (std::size_t s = 0, first_input = 0; s < scene.surfaces.size(); first_input += scene.surfaces[s++].mesh.triangles.size()) {
    const Surface& surface = scene.surfaces[s];
    const SubdividedMesh subdivided = subdivide_to_max_area_with_parents(surface.mesh, root_area);
    const TriangleMesh& pieces = subdivided.mesh;
    for (std::size_t t = 0; t < pieces.triangles.size(); ++t) {
      const Triangle tri = pieces.triangle(t);
      if (!(tri.area() > 0)) continue;
      const int root = static_cast<int>(forest.elements.size());
      const std::size_t parent = static_cast<std::size_t>(subdivided.parent[t]);
      forest.elements.push_back(make_element(tri, static_cast<int>(s), -1, root, static_cast<int>(first_input + parent)));
      forest.roots.push_back(root);
      forest.root_two_sided.push_back(parent < surface.two_sided.size() ? surface.two_sided[parent] : 0);
      grow_tree(forest, root, max_area, split_further);
      forest.root_block.emplace_back(root, static_cast<int>(forest.elements.size()));
    }
  }
  for (std::size_t e = 0; e < forest.elements.size(); ++e)
    if (forest.elements[e].first_child < 0) {
      forest.elements[e].leaf = static_cast<int>(forest.leaves.size());
      forest.leaves.push_back(static_cast<int>(e));
    }
  return forest;
}

void mark_enclosed(ElementForest& forest, const std::vector<char>& enclosed_leaf) {
  forest.enclosed.assign(forest.elements.size(), 0);
  forest.open_area.assign(forest.elements.size(), 0.0);
  for (std::size_t e = forest.elements.size(); e-- > 0;) {  // children come after their parent
    const Element& el = forest.elements[e];
    if (el.first_child < 0) {
      forest.enclosed[e] = enclosed_leaf[static_cast<std::size_t>(el.leaf)];
      forest.open_area[e] = forest.enclosed[e] ? 0.0 : el.area;
    } else {
      forest.enclosed[e] = 1;
      for (int k = 0; k < 4; ++k) {
        forest.enclosed[e] = forest.enclosed[e] && forest.enclosed[el.first_child + k];
        forest.open_area[e] += forest.open_area[el.first_child + k];
      }
    }
  }
}

int ElementForest::root_slot(int root) const {
  return static_cast<int>(std::lower_bound(roots.begin(), roots.end(), root) - roots.begin());
}

std::vector<Triangle> ElementForest::root_triangles() const {
  std::vector<Triangle> out;
  out.reserve(roots.size());
  for (int root : roots) out.push_back(elements[root].tri);
  return out;
}

std::vector<Patch> ElementForest::leaf_patches() const {
  std::vector<Patch> patches(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const Element& e = elements[leaves[i]];
    patches[i] = Patch{e.surface, e.tri, e.area, e.normal, e.input};
  }
  return patches;
}

}  // namespace lambert::hierarchical
