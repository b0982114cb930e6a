// The first stage of the solve: the scene as the methods mesh it.
//   - Re-centring: a scene far from the origin (a building at x ≈ 5e5, y ≈ 5.5e6 m) is solved about
//     its own centre, so that meshing, contacts, the occluder planes and every tolerance relative to
//     an element's size work on coordinates of the scene's size instead of the offset's.
//   - Slivers and over-tessellated regions: planar regions cut into thin strips, or into triangles
//     far smaller than the patches, are joined and triangulated again (mesh_ops.h,
//     merge_sliver_regions), so that patches follow the regions and not the input triangles.
//   - Contacts: surfaces are cut where other surfaces touch or cross them (imprint_contacts), so that
//     no patch straddles a box's footprint on a floor; the pieces in face-to-face contact are removed
//     and the two faces of sheets of zero thickness flagged (Surface::two_sided).
//   - Panes: a surface whose material transmits gets its back face (solver/pipeline/panes.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "solver/radiosity.h"

namespace lambert {

class PreparedScene {
 public:
  // with_panes: add the back faces of panes (the light's solve); the geometry alone (view factors,
  // radiant exchange: opaque, grey) takes each surface as given.
  PreparedScene(const Scene& scene, const SolveControl& control, bool with_panes = true);
  PreparedScene(const PreparedScene&) = delete;
  PreparedScene& operator=(const PreparedScene&) = delete;

  // The scene to mesh: the given one where nothing changed, else a re-centred or cut copy.
  const Scene& scene() const { return owned_ ? *owned_ : given_; }

  // Adds what the preparation found to a solution of scene(): its warnings and stats, and the
  // patches moved back to where the given scene lies.
  void finish(Solution& sol) const;

 private:
  void merge_and_cut(const SolveControl& control);

  const Scene& given_;
  std::optional<Scene> owned_;
  Vector3 shift_;
  bool cut_ = false;
  std::size_t sliver_regions_ = 0, fine_regions_ = 0, contact_triangles_cut_ = 0;
  double contact_area_m2_ = 0;
  std::vector<std::string> overlap_warnings_, merge_warnings_;
};

}  // namespace lambert
