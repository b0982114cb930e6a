// Mesh operations behind plain C++ types. CGAL lives only in mesh/cgal_ops.cpp and OpenMesh only in
// mesh/openmesh_ops.cpp, so that nothing else recompiles those heavy headers.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/mesh_file.h"  // read_mesh_file (Lambert's own readers)

namespace lambert {

// ---- CGAL (mesh/cgal_ops.cpp) ----------------------------------------------------------------

struct PolygonTriangulation {
  TriangleMesh mesh;           // triangles oriented like the polygon (counter-clockwise = front)
  std::string error;           // empty on success; otherwise says what is wrong (non-planar, ...)
  bool ok() const { return error.empty(); }
};

// Triangulates a planar simple polygon (convex or concave, no holes) robustly with CGAL.
// Errors: fewer than 3 vertices, repeated consecutive vertices, collinear (zero area),
// non-planar (a vertex farther than planarity_tolerance * polygon diameter from the best-fit plane),
// self-intersecting (not simple).
PolygonTriangulation triangulate_polygon(const std::vector<Point3>& polygon,
                                         double planarity_tolerance = 1e-6);

struct MeshHealth {
  std::vector<int> degenerate_triangles;          // zero area or repeated vertex index
  std::vector<std::pair<int, int>> self_intersections;  // pairs whose interiors cross or overlap (not
                                                        // pairs that only touch, e.g. at T-junctions)
  bool consistently_oriented = true;              // adjacent triangles agree on orientation
  bool manifold = true;                           // every edge has at most two triangles
  int boundary_edges = 0;                         // edges with one triangle (0: closed mesh)
};

// Health report of a mesh (CGAL Polygon Mesh Processing). Indices refer to mesh.triangles.
MeshHealth check_mesh(const TriangleMesh& mesh);

// Re-triangulates the planar regions of a mesh that contain slivers (triangles whose longest edge
// squared exceeds kSliverElongation times their area: about 20:1 and thinner, as CAD exports cut a
// wall into strips). The coplanar, same-facing triangles of such a region are joined exactly (CGAL
// Polygon_set_2), collinear boundary vertices dropped, and the union triangulated again (constrained
// Delaunay), so that patches follow the region's shape instead of its strips: a 3 m × 4 cm strip
// would otherwise carry one radiosity over 3 m, and every strip would be a separate occluder and
// input triangle. Regions without slivers are left as they are, unless `fine_area` > 0 and the
// region is over-tessellated: at least 64 triangles whose mean area is below fine_area (a CAD export
// that cuts a planar face into thousands of small triangles; the solver passes 1/16 of its patch
// area, so that patches are cut from the joined region at the patch size instead of one per input
// triangle). Orientation is kept; `tolerance` (relative to the mesh's bounding-box diagonal) decides
// coplanarity and collinearity.
inline constexpr double kSliverElongation = 40;
struct SliverMerge {
  TriangleMesh mesh;
  std::size_t slivers = 0;  // sliver triangles found
  std::size_t regions = 0;  // planar regions re-triangulated (for slivers or for being fine)
  std::size_t fine_regions = 0, fine_triangles = 0;  // of those, over-tessellated ones and their triangles
};
SliverMerge merge_sliver_regions(const TriangleMesh& mesh, double tolerance = 1e-9, double fine_area = 0);

struct ContactImprint {
  std::vector<TriangleMesh> meshes;  // the input meshes, with cut triangles replaced by their pieces
  std::size_t triangles_cut = 0;     // input triangles that were cut
  std::size_t segments = 0;          // contact segments imprinted
  // Per mesh and output triangle: 1 where the piece lies on a coplanar triangle of another mesh that
  // faces the other way. That is either contact (a box's bottom on a floor: nothing sees either face)
  // or the two faces of a sheet of zero thickness (both seen); only the solids around them tell.
  std::vector<std::vector<char>> on_opposite_face;
  std::vector<std::vector<int>> opposite_mesh;  // per output triangle: the mesh of that face, or −1
  struct Overlap { int mesh_a, mesh_b; double area; };
  std::vector<Overlap> overlaps;     // coplanar faces of two meshes facing the same way, overlapping
};

// Cuts every triangle along the segments where triangles of other meshes touch or cross its plane
// inside it (a box resting on a floor: the floor is cut along the box's footprint), so that no
// patch made from it straddles a contact line: the part under the box and the part beside it get
// their own patches, and light falling beside the box is not smeared under it. Segments along a
// triangle's own edges do not cut. Coplanar triangles facing the same way do not cut each other;
// coplanar triangles facing opposite ways (a box's bottom on the floor, a two-sided sheet) are each
// cut along the other's edges and the pieces on the other are flagged in on_opposite_face. Coplanar faces of two meshes that face the same way and overlap (a rug
// modelled in the floor's plane) are left as they are and listed in `overlaps` with the shared area. Pieces come from
// a constrained Delaunay triangulation (CGAL, exact predicates) of the triangle and its segments,
// keep the triangle's orientation and are not conforming with the neighbours (T-junctions are
// harmless to radiosity patches). `tolerance` is relative to the scene's bounding-box diagonal.
// Faces that lie in front of a triangle within `near_gap` (absolute) and within a twentieth of their
// own size (a panel 1 mm under a ceiling) cut it along their outline too (lies_just_in_front and
// flat_outline_edges, mesh/contacts.h): the part in their shadow gets its own patches, as if they
// touched.
ContactImprint imprint_contacts(const std::vector<TriangleMesh>& meshes, double tolerance = 1e-9,
                                double near_gap = 0);

// ---- OpenMesh (mesh/openmesh_ops.cpp) --------------------------------------------------------

// Splits triangles along their longest edge (conforming, geometry preserved exactly) until every
// triangle has area <= max_area and its longest edge <= √(8 max_area) (only slivers are split for
// length: a well-shaped triangle of area A has edges below √(4A)). Used to turn surfaces into
// radiosity patches. Lengths and areas within about 1e-6 of each other (and of the limits) count as
// equal, so that the patches do not depend on the scene's scale or placement.
// The input vertices keep their indices (midpoints are appended); output triangles are grouped by
// the input triangle they lie in, in input order; each keeps its parent's orientation. Triangles
// that cannot join a manifold, consistently oriented surface (fins, flipped faces of a soup) are
// bisected on their own (not conforming with their neighbours) instead of being dropped.
// A max_area that is not finite and > 0 returns the mesh unchanged.
TriangleMesh subdivide_to_max_area(const TriangleMesh& mesh, double max_area);

struct SubdividedMesh {
  TriangleMesh mesh;           // as returned by subdivide_to_max_area
  std::vector<int> parent;     // parent[t]: index of the input triangle that output triangle t lies in
};

// subdivide_to_max_area, also telling which input triangle (surface, material) each patch came from.
SubdividedMesh subdivide_to_max_area_with_parents(const TriangleMesh& mesh, double max_area);

}  // namespace lambert
