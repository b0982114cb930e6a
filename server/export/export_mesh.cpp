#include "server/export/export_mesh.h"

#include <algorithm>
#include <cstring>
#include <string_view>
#include <unordered_map>

namespace lambert {
namespace {

// Per patch: srgb (3), illuminance, luminance, blended together so that a smooth vertex's colour
// and values come from the same patches.
constexpr std::size_t kStride = 5;

struct Vertex {
  std::array<float, 3> position, normal, colour;
  float illuminance, luminance;
};

// Shares vertices whose every attribute has the same value (compared by their bits, with −0 made +0).
class Welder {
 public:
  explicit Welder(ExportSurface& out) : out_(out) {}
  void add(Vertex v) {
    for (auto* a : {&v.position, &v.normal, &v.colour})
      for (float& x : *a) x += 0.0f;  // −0 + 0 = +0 in round-to-nearest
    v.illuminance += 0.0f;
    v.luminance += 0.0f;
    std::string key(sizeof v, '\0');
    std::memcpy(key.data(), &v, sizeof v);
    const auto [it, added] = index_.try_emplace(std::move(key), static_cast<std::uint32_t>(out_.position_m.size()));
    if (added) {
      out_.position_m.push_back(v.position);
      out_.normal.push_back(v.normal);
      out_.colour.push_back(v.colour);
      out_.illuminance_lx.push_back(v.illuminance);
      out_.luminance_cd_m2.push_back(v.luminance);
    }
    out_.indices.push_back(it->second);
  }

 private:
  ExportSurface& out_;
  std::unordered_map<std::string, std::uint32_t> index_;
};

}  // namespace

ExportMesh export_mesh(const ResultModel& model, const ExportOptions& options) {
  ExportMesh mesh;
  mesh.name = model.name;
  mesh.shading = options.shading;
  mesh.white_cd_m2 = display_white(model, options.white_cd_m2);
  const std::size_t N = model.patches.size();
  std::vector<Triangle> triangles(N);
  std::vector<int> surface(N);
  std::vector<double> values(N * kStride);
  for (std::size_t i = 0; i < N; ++i) {
    const ResultPatch& p = model.patches[i];
    triangles[i] = p.triangle;
    surface[i] = p.surface;
    double* v = &values[i * kStride];
    v[0] = p.srgb[0], v[1] = p.srgb[1], v[2] = p.srgb[2], v[3] = p.illuminance_lx, v[4] = p.luminance_cd_m2;
  }
  const std::vector<double> at = corner_values(triangles, surface, values, kStride, options.shading);

  for (const std::string& name : model.surfaces) mesh.surfaces.push_back({name, {}, {}, {}, {}, {}, {}});
  std::vector<Welder> welders;
  welders.reserve(mesh.surfaces.size());
  for (ExportSurface& s : mesh.surfaces) welders.emplace_back(s);
  for (std::size_t i = 0; i < N; ++i) {
    const Vector3 n = triangles[i].normal();
    for (int k = 0; k < 3; ++k) {
      const Point3& p = triangles[i].v[k];
      const double* v = &at[(3 * i + k) * kStride];
      Vertex out{};
      out.position = {float(p.x * model.unit_m), float(p.y * model.unit_m), float(p.z * model.unit_m)};
      out.normal = {float(n.x), float(n.y), float(n.z)};
      for (int c = 0; c < 3; ++c) out.colour[c] = float(std::clamp(v[c] / mesh.white_cd_m2, 0.0, 1.0));
      out.illuminance = float(v[3]);
      out.luminance = float(v[4]);
      welders[surface[i]].add(out);
    }
  }
  for (const ResultProbe& p : model.probes) {
    ExportProbe& out = mesh.probes.emplace_back(ExportProbe{p.name, p.is_grid, p.nu, p.nv, {}, {}});
    for (const Point3& q : p.points)
      out.position_m.push_back({float(q.x * model.unit_m), float(q.y * model.unit_m), float(q.z * model.unit_m)});
    for (double E : p.illuminance_lx) out.illuminance_lx.push_back(float(E));
  }
  return mesh;
}

}  // namespace lambert
