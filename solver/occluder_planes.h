// Which pairs of points sets cannot be occluded at all, decided without rays. A triangle can block a
// segment only if the segment crosses the triangle's plane, so only triangles with some part of the
// scene strictly behind their plane can occlude anything ("occluder planes"; a convex room has none).
// Two patches that lie on one closed side of every occluder plane see each other wholly. Each patch
// gets a bit per occluder plane for "on its closed front side" and one for "on its closed back
// side"; a pair is clear when, for every plane, both share a side: a few word operations per pair
// instead of the 4 rays a wholly visible link costs. Model only what a scene needs: in an empty room
// every link is clear and no ray is traced.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

class OccluderPlanes {
 public:
  static constexpr int kWords = 4;
  static constexpr int kMaxPlanes = 64 * kWords;

  // The scene's triangles (the occluders). Scenes with more than kMaxPlanes distinct occluder planes,
  // or too large to classify cheaply, are not usable: every pair must then be traced.
  explicit OccluderPlanes(std::span<const Triangle> triangles);

  bool usable() const { return usable_; }
  std::size_t planes() const { return planes_.size(); }

  struct Sides {
    std::array<std::uint64_t, kWords> front{}, behind{};
  };
  // Sides of the occluder planes on which all of `points` lie (closed half-spaces, to a tolerance of
  // 1e-9 of the scene's size).
  Sides sides(std::span<const Point3> points) const;
  // Whether nothing can lie between the two point sets (each the vertices of a convex patch, or a
  // single point): true only if usable() and they share a closed side of every occluder plane.
  // Whether the points lie in front of every occluder plane: from there no back face can be seen.
  bool in_front_of_all(const Sides& a) const { return usable_ && a.front == all_; }
  bool clear(const Sides& a, const Sides& b) const {
    if (!usable_) return false;
    for (int w = 0; w < kWords; ++w)
      if (((a.front[w] & b.front[w]) | (a.behind[w] & b.behind[w])) != all_[w]) return false;
    return true;
  }

 private:
  struct Plane {
    Vector3 n;  // unit normal
    double d;   // n·(x − centre_) = d on the plane
  };
  std::vector<Plane> planes_;  // relative to centre_
  Point3 centre_;
  std::array<std::uint64_t, kWords> all_{};
  double eps_ = 0;
  bool usable_ = false;
};

}  // namespace lambert
