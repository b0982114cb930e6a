#include "server/viewfactors/vs3_scene.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "mesh/convex2d.h"

namespace lambert {
namespace {

// A polygon's plane: origin at its first corner, e1 along its first edge, n its normal (the front,
// for corners counter-clockwise seen from it), e2 = n × e1.
struct Frame {
  Point3 origin;
  Vector3 e1, e2, n;
  Point2d in(const Point3& p) const { return {dot(p - origin, e1), dot(p - origin, e2)}; }
  Point3 out(const Point2d& q) const { return origin + e1 * q[0] + e2 * q[1]; }
};

Frame frame_of(const std::vector<Point3>& polygon) {
  Vector3 newell{0, 0, 0};  // Newell's normal: twice the area vector of a planar polygon
  for (std::size_t k = 0; k < polygon.size(); ++k)
    newell = newell + cross(to_vector(polygon[k]), to_vector(polygon[(k + 1) % polygon.size()]));
  Frame f;
  f.origin = polygon[0];
  f.n = normalize(newell);
  f.e1 = normalize(polygon[1] - polygon[0]);
  f.e2 = cross(f.n, f.e1);
  return f;
}

// Triangles added to a mesh whose equal corners are shared.
class MeshBuilder {
 public:
  void triangle(const Point3& a, const Point3& b, const Point3& c) {
    mesh_.triangles.push_back({index(a), index(b), index(c)});
  }
  TriangleMesh take() { return std::move(mesh_); }

 private:
  int index(const Point3& p) {
    const auto [it, added] = at_.try_emplace({p.x, p.y, p.z}, static_cast<int>(mesh_.vertices.size()));
    if (added) mesh_.vertices.push_back(p);
    return it->second;
  }
  TriangleMesh mesh_;
  std::map<std::tuple<double, double, double>, int> at_;
};

// `polygon` (convex, counter-clockwise about its front) less `holes` (convex polygons in its plane),
// as triangles facing its front, or its back with `back`.
TriangleMesh region(const std::vector<Point3>& polygon, const std::vector<const std::vector<Point3>*>& holes,
                    bool back) {
  const Frame f = frame_of(polygon);
  Loop2d base;
  for (const Point3& p : polygon) base.push_back(f.in(p));
  ConvexPieces cutters, pieces;
  for (const std::vector<Point3>* hole : holes) {
    Loop2d loop;
    for (const Point3& p : *hole) loop.push_back(f.in(p));
    if (signed_area(loop) < 0) std::reverse(loop.begin(), loop.end());  // a null surface faces its base
    cutters.add(loop);
  }
  if (cutters.empty()) {
    pieces.add(base);
  } else {
    ConvexScratch scratch;
    convex_difference_pieces(base, cutters, 1e-12 * signed_area(base), pieces, scratch);
  }
  MeshBuilder mesh;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const std::span<const Point2d> piece = pieces[k];
    for (std::size_t j = 1; j + 1 < piece.size(); ++j) {
      const Point3 a = f.out(piece[0]), b = f.out(piece[j]), c = f.out(piece[j + 1]);
      if (back) mesh.triangle(a, c, b);
      else mesh.triangle(a, b, c);
    }
  }
  return mesh.take();
}

Surface scene_surface(std::string name, TriangleMesh mesh, std::size_t index) {
  Surface s;
  s.name = std::move(name);
  s.material = 0;
  s.mesh = std::move(mesh);
  s.pointer = "/surfaces/" + std::to_string(index);
  return s;
}

}  // namespace

Vs3SceneResult vs3_scene(std::string_view text, std::string_view name) {
  vs3::ReadResult read = vs3::read_vs3(text, name);
  if (!read.ok()) return {std::nullopt, std::move(read.errors)};
  const vs3::Input& in = *read.input;
  std::vector<std::string> errors;
  const std::string where = std::string(name) + ":";
  // The parts cut out of each surface: its subsurfaces and null surfaces.
  std::vector<std::vector<const std::vector<Point3>*>> holes(in.surfaces.size());
  for (const vs3::Surface& s : in.surfaces) {
    if (s.kind == vs3::SurfaceKind::Mask)
      errors.push_back(where + std::to_string(s.line) + ": surface " + std::to_string(s.number) +
                       " is a mask (M), which is not read here: View3D sets a mask's factor to its base to 1 by rule, "
                       "not from the geometry; make the covered part a subsurface (S with a base) or, if it should "
                       "not radiate, a null surface (N)");
    if (s.base > 0) holes[s.base - 1].push_back(&s.polygon);
  }
  if (!errors.empty()) return {std::nullopt, std::move(errors)};
  Vs3Scene out;
  out.controls = in.controls;
  out.title = in.title;
  out.warnings = std::move(read.input->warnings);
  Scene& scene = out.scene;
  scene.name = in.title;
  scene.grid = WavelengthGrid::from_list({555});
  scene.materials.push_back({"black", {0.0}, std::nullopt, Transmission::kNone, {}});
  std::vector<int> group_of_number(in.surfaces.size() + 1, -1);
  for (std::size_t k = 0; k < in.surfaces.size(); ++k) {
    const vs3::Surface& s = in.surfaces[k];
    const std::size_t index = scene.surfaces.size();
    if (s.kind == vs3::SurfaceKind::Radiating) {
      int group = s.combine > 0 ? group_of_number[s.combine] : static_cast<int>(out.groups.size());
      if (s.combine == 0) {
        out.groups.names.push_back(s.name);
        out.group_emissivity.push_back(s.emissivity);
      }
      group_of_number[s.number] = group;
      scene.surfaces.push_back(scene_surface(s.name, region(s.polygon, holes[k], false), index));
      out.groups.of_surface.push_back(group);
      out.emissivity.push_back(s.emissivity.value_or(1.0));
    } else if (s.kind == vs3::SurfaceKind::Null) {
      // Faces its base: the covered part, an occluder facing the way the base does.
      scene.surfaces.push_back(scene_surface(s.name, region(s.polygon, {}, true), index));
      out.groups.of_surface.push_back(-1);
      out.emissivity.push_back(1.0);
    } else {  // an obstruction: both faces, less its radiating subsurfaces
      scene.surfaces.push_back(scene_surface(s.name, region(s.polygon, holes[k], false), index));
      scene.surfaces.push_back(scene_surface(s.name + " (back)", region(s.polygon, holes[k], true), index + 1));
      out.groups.of_surface.insert(out.groups.of_surface.end(), {-1, -1});
      out.emissivity.insert(out.emissivity.end(), {1.0, 1.0});
    }
  }
  return {std::move(out), {}};
}

}  // namespace lambert
