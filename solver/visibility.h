// Ray-traced visibility between points of the scene (Embree 3). All Embree types stay in
// visibility.cpp. The scene is re-centred on its bounding-box centre before it is handed to Embree's
// single-precision BVH, so geo-referenced coordinates (x ≈ 5e5 m) lose no precision.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

struct Segment { Point3 from, to; };

class Visibility {
 public:
  // How the rays of estimates (estimate_visible: visible fractions averaged over several rays, as
  // for links between patches) are traced. Every other ray is watertight: Embree's robust mode, so
  // that a ray through the seam between two triangles cannot slip out of a closed room (the closure
  // probe, a point light's single shadow ray). `fast` traces estimates in a second BVH over the same
  // triangles without robust mode: about 12 % less refinement time in the sphere rooms of
  // docs/BENCHMARKS.md, for about 60 bytes per triangle. A ray there may pass a seam within float
  // precision of an edge; in a fraction averaged over 4 to 64 rays that is far below the sampling
  // error (the 245 774-triangle lit sphere room: surface means within 3e-7).
  enum class Estimates { watertight, fast };

  // Occluders: every triangle of the scene (metres). Throws std::runtime_error if Embree fails.
  explicit Visibility(std::span<const Triangle> occluders, Estimates estimates = Estimates::watertight);
  ~Visibility();
  Visibility(const Visibility&) = delete;
  Visibility& operator=(const Visibility&) = delete;

  // Whether the open segment between the points is unobstructed. The ends are excluded by a small
  // distance (a few float ulps of the scene's size) so that rays leaving or reaching a surface do not
  // hit that surface itself.
  bool visible(const Point3& from, const Point3& to) const;
  // A point on a surface moved off it along the surface's normal by a small multiple of the float
  // resolution of the scene's size: a ray that leaves or reaches a surface at a grazing angle would
  // otherwise hit that surface itself within float precision. Use for every surface end point.
  Point3 lift(const Point3& p, const Vector3& unit_normal) const { return p + unit_normal * lift_m_; }

  // Index (into the occluder list) of the first triangle the open segment hits, or -1 if none.
  int first_hit(const Point3& from, const Point3& to) const;

  // A length that takes any point of the scene out of its bounding box in any direction (m), for
  // shadow rays towards directional light.
  double scene_extent() const;
  // Batch form (uses Embree's stream API): visible[k] = 1 if segment k is unobstructed.
  void visible(std::span<const Segment> segments, std::span<std::uint8_t> visible) const;
  // The same for rays whose verdicts are averaged (Estimates above): traced in the fast BVH if the
  // Visibility was built with one, else as visible().
  void estimate_visible(std::span<const Segment> segments, std::span<std::uint8_t> visible) const;

  // Batch form of first_hit (Embree's stream API): hits[k] = first_hit(segments[k]).
  void first_hits(std::span<const Segment> segments, std::span<int> hits) const;

  std::uint64_t rays_traced() const;  // total since construction (all threads)

  // Clear glass (solver/glazing.h). Marks occluders as specular panes: channel_of_occluder[t] is the
  // pane channel of occluder t (its material's; −1: opaque), `occluders` the constructor's. Every other method still takes a pane
  // for opaque; transmitted() of a view (through_panes) lets rays cross it. `name_of(t)`: the
  // surface occluder t belongs to, for the error that refuses a ray crossing two panes.
  void set_specular_panes(std::span<const Triangle> occluders, std::vector<int> channel_of_occluder,
                          std::function<std::string(int)> name_of);
  // A view sharing this Visibility's BVH whose transmitted() counts the rays that cross one pane of
  // `channel` and nothing else. Kept alive by nothing: the Visibility must outlive its views.
  std::unique_ptr<Visibility> through_panes(int channel) const;
  // What share of a ray from `from` to `to` arrives. Not a view: 1 if visible() else 0. A view of
  // channel c: g(θ) (solver/glazing.h) if the open segment meets exactly one pane, of channel c, at
  // θ from its normal, and nothing else; else 0 (the unobstructed rays are the Visibility's own).
  // Throws std::invalid_argument where the segment crosses two panes (a ray loses τ(λ) per pane:
  // one spectral factor per channel cannot say how many it crossed).
  double transmitted(const Point3& from, const Point3& to) const;
  // A view's pane channel, or −1 (lights that take no rays, the sky, ask which panes to look through).
  int channel() const { return channel_; }

 private:
  struct Impl;
  Visibility() = default;
  std::shared_ptr<Impl> impl_;  // shared with the views
  int channel_ = -1;            // a view's pane channel, or −1
  double lift_m_ = 0;  // lift()'s distance, Impl::epsilon_m (inline: the link rays lift two points each)
};

}  // namespace lambert
