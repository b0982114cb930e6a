#include "solver/pipeline/prepare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <variant>

#include "mesh/mesh_ops.h"
#include "solver/pipeline/panes.h"
#include "solver/solids.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

// The shift that brings a scene far from the origin to it, per axis: the centre of the surfaces'
// bounding box on the axes where it lies more than ten times the box's diagonal away, else 0. There
// every coordinate lies within a factor 2 of the centre, so x − c is exact (Sterbenz) and so is
// (x − c) + c: the shifted scene is the same geometry, and its output vertices come back unchanged.
Vector3 recentring_shift(const Scene& scene) {
  Bounds3 box;
  for (const Surface& s : scene.surfaces)
    for (const Point3& v : s.mesh.vertices) box.add(v);
  if (box.empty()) return {};
  const double size = length(box.diagonal());
  const Point3 c = box.center();
  auto axis = [&](double centre) { return std::abs(centre) > 10 * size ? centre : 0.0; };
  return {axis(c.x), axis(c.y), axis(c.z)};
}

// Pieces that lie on an opposite-facing coplanar face (imprint_contacts, on_opposite_face) are either
// contact — a box's bottom on a floor, where the space in front of one of the two faces is inside the
// other's solid — or the two faces of a sheet of zero thickness, in front of both of which is open
// space. A hemisphere probe on each side of the piece tells them apart: if every ray from one side
// hits the back of a surface, that side is inside a solid and the piece is contact, seen by nothing,
// and removed. `surfaces`: the meshes as given (imprint's are cut). Returns the area removed (both
// faces counted).
double remove_contact_pieces(ContactImprint& imprint, const std::vector<Surface>& surfaces) {
  bool any = false;
  for (const std::vector<char>& flags : imprint.on_opposite_face)
    any |= std::any_of(flags.begin(), flags.end(), [](char f) { return f != 0; });
  if (!any) return 0;
  const std::vector<char> solid = surfaces_bounding_solids(surfaces);
  std::vector<Triangle> all;
  std::vector<Vector3> normals;
  std::vector<char> sheet;
  for (std::size_t m = 0; m < imprint.meshes.size(); ++m)
    for (std::size_t t = 0; t < imprint.meshes[m].triangles.size(); ++t) {
      all.push_back(imprint.meshes[m].triangle(t));
      // A flagged piece and its partner coincide, and a ray meets either of them: from inside a box
      // pushed into a room's corner it may meet the room's wall (facing into the box) instead of the
      // box's own side. Where either of the two bounds a solid, the pair counts as a back face (a
      // zero normal), whichever of them is hit. Otherwise the two are a sheet's faces, and one of
      // them faces the ray whichever is hit: a front face (a sheet facing another across a narrow
      // gap would otherwise make the gap look like a solid's inside).
      const bool flagged = imprint.on_opposite_face[m][t] != 0;
      const int other = imprint.opposite_mesh[m][t];
      const bool ambiguous = flagged && (solid[m] || (other >= 0 && solid[other]));
      normals.push_back(ambiguous ? Vector3{} : all.back().normal());
      sheet.push_back(flagged && !ambiguous);
    }
  const Visibility vis(all);
  constexpr int kRays = 64;  // a solid's interior sends every ray to a back face; one escape ends it
  auto inside_a_solid = [&](const Triangle& side, const Vector3& n, std::size_t seed) {
    return probe_hemisphere(side, n, seed, kRays, vis, [&](int hit, const Vector3& d) {
             return !sheet[hit] && dot(normals[hit], d) >= 0;
           }) == Hemisphere::Enclosed;
  };
  double removed = 0;
  std::size_t index = 0;
  for (std::size_t m = 0; m < imprint.meshes.size(); ++m) {
    TriangleMesh& mesh = imprint.meshes[m];
    std::vector<std::array<int, 3>> kept;
    std::vector<char> kept_flags;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t, ++index) {
      if (imprint.on_opposite_face[m][t]) {
        const Triangle& front = all[index];
        const Triangle back{{front.v[0], front.v[2], front.v[1]}};
        const Vector3 n = front.normal();
        if (inside_a_solid(front, n, index) || inside_a_solid(back, -n, index)) {
          removed += front.area();
          continue;
        }
      }
      kept.push_back(mesh.triangles[t]);
      kept_flags.push_back(imprint.on_opposite_face[m][t]);
    }
    mesh.triangles = std::move(kept);
    imprint.on_opposite_face[m] = std::move(kept_flags);  // what is left flagged: two-sided sheets
  }
  return removed;
}

std::string area_text(double area) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", area);
  return text;
}

std::string listed(const std::vector<std::string>& names, std::size_t of) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list + (names.size() < of ? ", ..." : "");
}

}  // namespace

PreparedScene::PreparedScene(const Scene& scene, const SolveControl& control, bool with_panes) : given_(scene) {
  shift_ = recentring_shift(scene);
  if (shift_.x != 0 || shift_.y != 0 || shift_.z != 0) {
    Scene& moved = owned_.emplace(scene);
    for (Surface& s : moved.surfaces)
      for (Point3& v : s.mesh.vertices) v = v - shift_;
    for (Light& light : moved.lights)
      if (auto* point = std::get_if<PointLight>(&light)) point->position = point->position - shift_;
      else if (auto* luminaire = std::get_if<LuminaireLight>(&light)) luminaire->position = luminaire->position - shift_;
    for (Probe& probe : moved.probes)
      for (Point3& p : probe.points) p = p - shift_;
  }
  merge_and_cut(control);
  if (with_panes && has_panes(this->scene())) add_pane_back_faces(owned_ ? *owned_ : owned_.emplace(given_));
}

void PreparedScene::merge_and_cut(const SolveControl& control) {
  const Scene& placed = this->scene();
  std::vector<TriangleMesh> meshes;
  meshes.reserve(placed.surfaces.size());
  // Over-tessellated regions are those whose input triangles are on average below 1/16 of the
  // patch size: joined, they give patches of the patch size instead of one per input triangle.
  std::size_t slivers = 0, fine_triangles = 0;
  std::size_t sliver_surface_count = 0, fine_surface_count = 0;  // surfaces with such regions
  std::vector<std::string> sliver_surfaces, fine_surfaces;
  const double patch_area = placed.meshing.max_patch_area_m2.value_or(default_max_patch_area(placed));
  const double fine_area = patch_area / 16;
  for (const Surface& s : placed.surfaces) {
    if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
    SliverMerge merged = merge_sliver_regions(s.mesh, 1e-9, fine_area);
    const std::size_t for_slivers = merged.regions - merged.fine_regions;
    slivers += for_slivers > 0 ? merged.slivers : 0;
    sliver_regions_ += for_slivers;
    fine_regions_ += merged.fine_regions;
    fine_triangles += merged.fine_triangles;
    sliver_surface_count += for_slivers > 0;
    fine_surface_count += merged.fine_regions > 0;
    if (for_slivers > 0 && sliver_surfaces.size() < 3) sliver_surfaces.push_back("\"" + s.name + "\"");
    if (merged.fine_regions > 0 && fine_surfaces.size() < 3) fine_surfaces.push_back("\"" + s.name + "\"");
    meshes.push_back(std::move(merged.mesh));
  }
  // Faces closer to a surface than a twentieth of the patch size (and of their own size) cut it along
  // their outline: the light under them comes through the gap only, and falls to nothing within a
  // few gap widths, so a patch across the outline would average a lit part with a dark one (a panel
  // 1 mm under the ceiling of docs/BENCHMARKS.md's lit sphere room: the ceiling's patches across its
  // edge were 11 % low against the converged solve).
  const double near_gap = std::sqrt(patch_area) / 20;
  ContactImprint imprint = imprint_contacts(meshes, 1e-9, near_gap);
  const double contact_area = remove_contact_pieces(imprint, placed.surfaces);
  for (const auto& o : imprint.overlaps)
    overlap_warnings_.push_back("surfaces \"" + placed.surfaces[o.mesh_a].name + "\" and \"" +
                                placed.surfaces[o.mesh_b].name + "\" overlap in one plane over " + area_text(o.area) +
                                " m² (coplanar faces facing the same way): both radiate from the same place, so "
                                "light there is counted twice; remove one or lift it off the other");
  if (fine_regions_ > 0)
    merge_warnings_.push_back(std::to_string(fine_triangles) + " input triangles in " + std::to_string(fine_regions_) +
                              " planar regions (surfaces " + listed(fine_surfaces, fine_surface_count) +
                              "), each on average smaller than 1/16 of meshing.max_patch_area, were joined and "
                              "triangulated again: patches are cut from the regions at meshing.max_patch_area, "
                              "not one per input triangle (set a smaller max_patch_area for finer patches)");
  if (sliver_regions_ > 0)
    merge_warnings_.push_back(std::to_string(slivers) + " sliver triangles (thinner than about 1:20) in " +
                              std::to_string(sliver_regions_) + " planar regions (surfaces " +
                              listed(sliver_surfaces, sliver_surface_count) +
                              ") were joined and triangulated again: patches follow the regions, not the strips");
  if (imprint.triangles_cut == 0 && sliver_regions_ == 0 && fine_regions_ == 0) return;
  cut_ = true;
  contact_triangles_cut_ = imprint.triangles_cut;
  contact_area_m2_ = contact_area;
  Scene& cut = owned_ ? *owned_ : owned_.emplace(given_);
  for (std::size_t s = 0; s < cut.surfaces.size(); ++s) {
    cut.surfaces[s].mesh = std::move(imprint.meshes[s]);
    cut.surfaces[s].two_sided = std::move(imprint.on_opposite_face[s]);
  }
}

void PreparedScene::finish(Solution& sol) const {
  if (cut_) {
    sol.stats.contact_triangles_cut = contact_triangles_cut_;
    sol.stats.contact_area_m2 = contact_area_m2_;
    if (contact_area_m2_ > 0)
      sol.warnings.push_back(area_text(contact_area_m2_) + " m² of surface lie face to face on other surfaces (e.g. a "
                             "box's bottom on a floor): that contact area is hidden and left out of the patches");
  }
  sol.warnings.insert(sol.warnings.end(), overlap_warnings_.begin(), overlap_warnings_.end());
  sol.stats.sliver_regions_remeshed = sliver_regions_;
  sol.stats.fine_regions_remeshed = fine_regions_;
  sol.warnings.insert(sol.warnings.end(), merge_warnings_.begin(), merge_warnings_.end());
  if (shift_.x != 0 || shift_.y != 0 || shift_.z != 0)
    for (Patch& patch : sol.patches)
      for (Point3& v : patch.triangle.v) v = v + shift_;
}

}  // namespace lambert
