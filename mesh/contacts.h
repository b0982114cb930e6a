// Where two triangles of a scene touch, for imprint_contacts (mesh_ops.h): the segment along which
// one meets the other's plane, and the area two coplanar ones share. Plain geometry, in a unit of its
// own so that the CGAL unit that cuts the triangles stays small.
#pragma once

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

}  // namespace lambert
