// Which pairs of point sets cannot be occluded at all, decided without rays. A triangle can block a
// segment only if the segment crosses the triangle's plane inside the triangle, so:
//  - only triangles with some part of the scene strictly behind their plane can occlude anything
//    ("occluders"; a convex room has none), and
//  - a segment whose ends lie on one closed side of an occluder's plane, or both outside the extent
//    of the occluders in that plane, passes that plane's occluders.
// The occluders are grouped by plane; each group keeps its plane and the four sides of its bounding
// rectangle in the plane. Every patch (and probe point) gets, per group, a byte of "on the closed
// outer side of this bounding plane" bits, in front and behind forms: a pair is clear when for every
// group some bounding plane has both on one side — a few word operations per pair instead of the 4
// rays a wholly visible link costs. Model only what a scene needs: in an empty room every link is
// clear and no ray is traced.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

class OccluderPlanes {
 public:
  static constexpr int kMaxGroups = 128;                // planes holding occluders
  static constexpr int kWords = kMaxGroups * 8 / 64;  // one byte per group

  // The scene's triangles (the occluders). Scenes with more than kMaxGroups distinct occluder planes,
  // or too large to classify cheaply, are not usable: every pair must then be traced. `receivers`:
  // points off the triangles that will be asked about too (probe points in the air), which count as
  // part of the scene: a plate with nothing behind it but a probe occludes that probe.
  explicit OccluderPlanes(std::span<const Triangle> triangles, std::span<const Point3> receivers = {});

  bool usable() const { return usable_; }
  std::size_t planes() const { return groups_.size(); }

  struct Sides {
    std::array<std::uint64_t, kWords> front{}, behind{};
  };
  // The sides on which all of `points` lie, closed half-spaces to a tolerance of 1e-9 of the scene's
  // size. Bit 0 of a group's byte is its plane (front: in front of it, behind: behind it); bits 1–4
  // are the four sides of its bounding rectangle (set in `front` only: outside that side).
  Sides sides(std::span<const Point3> points) const;
  // Whether the points lie in front of every occluder plane: from there no back face can be seen.
  bool in_front_of_all(const Sides& a) const {
    if (!usable_) return false;
    for (int w = 0; w < words_; ++w)
      if ((a.front[w] & low_bits_[w]) != low_bits_[w]) return false;  // bit 0 of a byte: the plane
    return true;
  }
  // Whether nothing can lie between the two point sets (each the vertices of a convex patch, or a
  // single point): true only if usable() and, for every group, both lie on one side of its plane or
  // outside one side of its bounding rectangle.
  bool clear(const Sides& a, const Sides& b) const {
    if (!usable_) return false;
    for (int w = 0; w < words_; ++w) {
      std::uint64_t ok = (a.front[w] & b.front[w]) | (a.behind[w] & b.behind[w]);
      ok |= ok >> 4, ok |= ok >> 2, ok |= ok >> 1;  // bit 0 of each byte: any of its bits 0–7
      if ((ok & low_bits_[w]) != low_bits_[w]) return false;
    }
    return true;
  }

 private:
  struct Plane {
    Vector3 n;  // unit normal
    double d;   // n·(x − centre_) = d on the plane
  };
  struct Group {
    Plane plane;
    std::array<Plane, 4> sides;  // outward normals in the plane; outside: n·(x − centre_) ≥ d
  };
  std::vector<Group> groups_;
  std::array<std::uint64_t, kWords> low_bits_{};  // bit 0 of every used group's byte
  int words_ = 0;
  Point3 centre_;
  double eps_ = 0;
  bool usable_ = false;
};

}  // namespace lambert
