// Where two triangles of a scene touch, for imprint_contacts (mesh_ops.h): the segment along which
// one meets the other's plane, and the area two coplanar ones share. Plain geometry, in a unit of its
// own so that the CGAL unit that cuts the triangles stays small.
#pragma once

#include <algorithm>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

// The segment a→b where triangle u meets the plane of t (through t.v[0], unit normal n), if a part
// of positive length of it lies inside t and not along an edge of t; false otherwise, or if u lies
// in the plane. Distances below eps count as zero. The segment is returned whole, not clipped to t:
// the triangulation then computes its crossings with t's edges itself and splits both there, where
// a clipped end point rounded beside an edge would leave sliver pieces.
bool contact_segment(const Triangle& t, const Vector3& n, const Triangle& u, double eps, Point3& a, Point3& b);

// The area that triangle u covers of triangle t, the two coplanar (t's plane: through t.v[0], unit
// normal n), exact up to the rounding of their corners into t's plane (convex_difference).
double coplanar_shared_area(const Triangle& t, const Vector3& n, const Triangle& u);

// Per triangle of `mesh`, bit k set where its edge v[k]→v[k+1] lies on the outline of a flat region
// of the mesh: not shared with another of its triangles in the same plane (corners welded by position,
// so faces that carry their own copies of shared corners still meet). A panel of two triangles has
// four outline edges; its diagonal is not one.
std::vector<unsigned char> flat_outline_edges(const TriangleMesh& mesh);

// How far in front of a surface face u may lie and still cut it along its outline: `gap`, and at
// most a twentieth of u's longest edge.
inline double near_slab(const Triangle& u, double gap) { return std::min(gap, u.max_edge_length() / 20); }

// Whether u lies just in front of t, in the slab between t's plane and a height h above it (every
// corner at a height in [−eps, h] along t's unit normal n, one above eps), h = near_slab(u, gap),
// and its shadow on t's plane covers more of t than rounding would (1e-3 of the smaller area: not a
// face beside t, one step up). Light then reaches the part of t under u only through the gap, so
// the shadow's edge there is as sharp as the gap is narrow against u: imprint_contacts cuts t along
// u's outline, and no patch averages the lit side with the dark one. (A face small against its gap
// casts no such shadow: light comes in from every side.)
bool lies_just_in_front(const Triangle& t, const Vector3& n, const Triangle& u, double eps, double gap);

}  // namespace lambert
