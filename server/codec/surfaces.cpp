// "surfaces" (SPEC §1): a name, a material, one geometry (polygon, inline mesh or mesh file, the
// last two with an optional transform) and an optional emission. Lengths become metres once the
// geometry is complete, so the solver sees SI units only.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string_view>
#include <utility>
#include <vector>

#include "mesh/mesh_ops.h"
#include "server/codec/mesh_files.h"
#include "server/codec/sections.h"
#include "server/codec/spectra.h"
#include "server/codec/thermal.h"

namespace lambert::codec {
namespace {

// ---- geometry helpers -------------------------------------------------------------------------

struct Transform {
  Vector3 scale{1, 1, 1};
  Vector3 rotate_deg{0, 0, 0};
  Vector3 translate{0, 0, 0};
  bool flips() const { return scale.x * scale.y * scale.z < 0; }
  // p' = Rz Ry Rx (s ⊙ p) + t: scale, then rotate about x, y, z in that order, then translate.
  Point3 apply(const Point3& p) const {
    Vector3 v{p.x * scale.x, p.y * scale.y, p.z * scale.z};
    const auto [sx, cx] = sincos_degrees(rotate_deg.x);
    v = {v.x, cx * v.y - sx * v.z, sx * v.y + cx * v.z};
    const auto [sy, cy] = sincos_degrees(rotate_deg.y);
    v = {cy * v.x + sy * v.z, v.y, -sy * v.x + cy * v.z};
    const auto [sz, cz] = sincos_degrees(rotate_deg.z);
    v = {cz * v.x - sz * v.y, sz * v.x + cz * v.y, v.z};
    return to_point(v + translate);
  }
};

double mesh_area(const TriangleMesh& mesh) {
  double a = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) a += mesh.triangle(t).area();
  return a;
}

// ---- geometries -------------------------------------------------------------------------------

std::optional<TriangleMesh> decode_polygon(Decoder& d, const json& j, const std::string& p) {
  if (!d.array(j, p, 3)) return std::nullopt;
  std::vector<Point3> points;
  bool ok = true;
  for (std::size_t k = 0; k < j.size(); ++k) {
    auto q = d.point(j[k], index_ptr(p, k));
    if (q) points.push_back(*q);
    else ok = false;
  }
  if (!ok) return std::nullopt;
  // Triangulated in scene units: the planarity tolerance is relative to the polygon's size.
  PolygonTriangulation tri = triangulate_polygon(points, 1e-6);
  if (!tri.ok()) {
    d.error(p, tri.error);
    return std::nullopt;
  }
  for (Point3& v : tri.mesh.vertices) v = d.metres(v);
  return std::move(tri.mesh);
}

// One entry of an inline mesh's "triangles" that is not three distinct in-range unsigned
// integers, read again to say what is wrong with it. vertex_count < 0: the vertices were no array.
std::optional<std::array<int, 3>> checked_triangle(Decoder& d, const json& tri,
                                                   const std::string& pk, long long vertex_count) {
  if (!tri.is_array() || tri.size() != 3) {
    d.error(pk, "expected 3 vertex indices [i, j, k], got " +
                    (tri.is_array() ? std::to_string(tri.size()) + " entries" : a_type(tri)));
    return std::nullopt;
  }
  std::array<int, 3> idx{};
  bool tri_ok = true;
  for (std::size_t c = 0; c < 3; ++c) {
    const std::string pc = index_ptr(pk, c);
    auto v = d.whole(tri[c], pc, 0, std::numeric_limits<int>::max());
    if (!v) { tri_ok = false; continue; }
    if (vertex_count >= 0 && *v >= vertex_count) {
      d.error(pc, "vertex index " + std::to_string(*v) + " is out of range (the mesh has " +
                      std::to_string(vertex_count) + " vertices)");
      tri_ok = false;
      continue;
    }
    idx[c] = static_cast<int>(*v);
  }
  if (tri_ok && (idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2])) {
    d.error(pk, "triangle repeats a vertex index (degenerate)");
    tri_ok = false;
  }
  return tri_ok ? std::optional<std::array<int, 3>>(idx) : std::nullopt;
}

bool read_triangles(Decoder& d, const json& jt, const std::string& pt, long long vertex_count,
                    TriangleMesh& mesh) {
  bool ok = true;
  mesh.triangles.reserve(jt.size());
  for (std::size_t k = 0; k < jt.size(); ++k) {
    const json& tri = jt[k];
    if (tri.is_array() && tri.size() == 3 && tri[0].is_number_unsigned() &&
        tri[1].is_number_unsigned() && tri[2].is_number_unsigned()) {  // fast path
      const auto a = tri[0].get<std::uint64_t>(), b = tri[1].get<std::uint64_t>(),
                 c = tri[2].get<std::uint64_t>();
      const auto n = static_cast<std::uint64_t>(std::max(vertex_count, 0LL));
      if (a < n && b < n && c < n && a != b && b != c && a != c) {
        mesh.triangles.push_back({static_cast<int>(a), static_cast<int>(b), static_cast<int>(c)});
        continue;
      }
    }
    if (auto idx = checked_triangle(d, tri, index_ptr(pt, k), vertex_count))
      mesh.triangles.push_back(*idx);
    else ok = false;
  }
  return ok;
}

std::optional<TriangleMesh> decode_inline_mesh(Decoder& d, const json& j, const std::string& p) {
  if (!d.object(j, p, {"vertices", "triangles"})) return std::nullopt;
  const json* jv = d.required(j, p, "vertices");
  const json* jt = d.required(j, p, "triangles");
  TriangleMesh mesh;
  bool ok = jv && jt;
  const std::string pv = p + "/vertices", pt = p + "/triangles";
  if (jv && d.array(*jv, pv, 3)) {
    mesh.vertices.reserve(jv->size());
    for (std::size_t k = 0; k < jv->size(); ++k) {
      if (auto q = valid_triple((*jv)[k], true)) {
        mesh.vertices.push_back(to_point(*q));
      } else {
        d.point((*jv)[k], index_ptr(pv, k));  // reports what is wrong
        ok = false;
      }
    }
  } else {
    ok = false;
  }
  // Indices are range-checked against the vertex array as written, even if some vertex was bad.
  const long long vertex_count = jv && jv->is_array() ? static_cast<long long>(jv->size()) : -1;
  if (!(jt && d.array(*jt, pt, 1) && read_triangles(d, *jt, pt, vertex_count, mesh))) ok = false;
  return ok ? std::optional<TriangleMesh>(std::move(mesh)) : std::nullopt;
}

std::optional<Transform> decode_transform(Decoder& d, const json& j, const std::string& p) {
  if (!d.object(j, p, {"scale", "rotate_deg", "translate"})) return std::nullopt;
  Transform t;
  bool ok = true;
  if (const json* s = d.member(j, "scale")) {
    const std::string ps = p + "/scale";
    if (s->is_number()) {
      auto v = d.number(*s, ps);
      if (v && *v == 0) d.error(ps, "scale must not be zero");
      if (v && *v != 0) t.scale = {*v, *v, *v};
      else ok = false;
    } else if (auto v = d.triple(*s, ps, false)) {
      for (std::size_t k = 0; k < 3; ++k)
        if ((*v)[k] == 0) {
          d.error(index_ptr(ps, k), "scale must not be zero");
          ok = false;
        }
      t.scale = *v;
    } else {
      ok = false;
    }
  }
  if (const json* r = d.member(j, "rotate_deg")) {
    if (auto v = d.triple(*r, p + "/rotate_deg", false)) t.rotate_deg = *v;
    else ok = false;
  }
  if (const json* tr = d.member(j, "translate")) {
    if (auto v = d.triple(*tr, p + "/translate", true)) t.translate = *v;
    else ok = false;
  }
  return ok ? std::optional<Transform>(t) : std::nullopt;
}

// Moves a mesh by its transform; nullopt (reported at pt) when a vertex leaves the coordinate limit.
std::optional<TriangleMesh> transformed(Decoder& d, TriangleMesh mesh, const Transform& transform,
                                        const std::string& pt) {
  for (Point3& v : mesh.vertices) {
    v = transform.apply(v);
    if (!within_coordinate_limit(v)) {
      d.error(pt, "moves vertices beyond the coordinate limit of 1e9 scene units");
      return std::nullopt;
    }
  }
  // A mirroring scale turns counter-clockwise into clockwise: reverse the winding so the side
  // that was the front in the model stays the front.
  if (transform.flips())
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

// Geometry: exactly one of polygon, mesh, file; in metres.
std::optional<TriangleMesh> surface_geometry(Decoder& d, const json& j, const std::string& p) {
  std::vector<std::string_view> kinds;
  for (std::string_view k : {"polygon", "mesh", "file"})
    if (j.contains(k)) kinds.push_back(k);
  std::optional<Transform> transform;
  const json* jtransform = d.member(j, "transform");
  if (jtransform) {
    transform = decode_transform(d, *jtransform, p + "/transform");
    if (j.contains("polygon"))
      d.error(p + "/transform", "transform applies only to mesh and file surfaces; give the "
                                "polygon's points where they belong");
  }
  if (kinds.empty()) {
    d.error(p, "a surface needs one of polygon, mesh or file");
    return std::nullopt;
  }
  if (kinds.size() > 1) {
    d.error(p, "has both " + join(kinds, " and ") + "; give exactly one");
    return std::nullopt;
  }
  if (kinds.front() == "polygon") return decode_polygon(d, j.at("polygon"), p + "/polygon");
  const bool is_inline = kinds.front() == "mesh";
  const std::string pg = p + (is_inline ? "/mesh" : "/file");
  std::optional<TriangleMesh> mesh = is_inline ? decode_inline_mesh(d, j.at("mesh"), pg)
                                               : decode_file_mesh(d, j.at("file"), pg);
  if (mesh && jtransform && !transform) mesh.reset();  // transform already reported
  if (mesh && transform) mesh = transformed(d, std::move(*mesh), *transform, p + "/transform");
  if (mesh) {
    for (Point3& v : mesh->vertices) v = d.metres(v);
    check_mesh_health(d, *mesh, pg, is_inline ? MeshSource::Inline : MeshSource::File);
  }
  return mesh;
}

// ---- emission ---------------------------------------------------------------------------------

// "lobe": "lambert" or {"phong": n}; sets emission.lobe_exponent. false after an error.
bool decode_lobe(Decoder& d, const json& lobe, const std::string& pl, Emission& emission) {
  if (lobe.is_string()) {
    if (lobe.get<std::string>() == "lambert") return true;
    d.error(pl, "unknown lobe " + quote_text(lobe.get<std::string>()) +
                    "; expected \"lambert\" or {\"phong\": n}");
    return false;
  }
  if (lobe.is_object()) {
    d.unknown_keys(lobe, pl, {"phong"});
    const json* n = d.required(lobe, pl, "phong");
    auto v = n ? d.number_in(*n, pl + "/phong", 1, true, kMaxLobeExponent, true) : std::nullopt;
    if (v) emission.lobe_exponent = *v;
    return v.has_value();
  }
  d.error(pl, "expected \"lambert\" or {\"phong\": n}, got " + a_type(lobe));
  return false;
}

// Surface emission (SPEC §1): exitance R or radiance L, a lobe, and optionally one total.
// With lobe exponent n the on-axis radiance is L = R (n+1)/(2π) (the lobe normalisation of SPEC
// "Light models"; n = 1 gives L = R/π). The Scene stores R.
std::optional<Emission> decode_emission(Decoder& d, const json& j, const std::string& p,
                                        std::optional<double> area_m2) {
  if (!d.object(j, p, with_totals({"exitance", "radiance", "lobe"}))) return std::nullopt;
  Emission emission;
  bool ok = true;
  if (const json* lobe = d.member(j, "lobe")) ok = decode_lobe(d, *lobe, p + "/lobe", emission);
  const double n = emission.lobe_exponent;

  const json* jr = d.member(j, "exitance");
  const json* jl = d.member(j, "radiance");
  if (jr && jl) {
    d.error(p, "give exitance or radiance, not both");
    ok = false;
  } else if (!jr && !jl) {
    d.error(p, "an emission needs exitance or radiance");
    ok = false;
  }
  const std::string ps = p + (jr ? "/exitance" : "/radiance");
  std::optional<std::vector<double>> shape;
  if (jr || jl) shape = spectrum(d, jr ? *jr : *jl, ps, SpectrumRole::Emission);
  const auto t = total(d, j, p,
                       {"luminous_exitance_lm_m2", "radiant_exitance_W_m2", "luminance_cd_m2",
                        "radiance_W_m2_sr", "luminous_flux_lm", "radiant_flux_W",
                        "luminous_intensity_cd", "radiant_intensity_W_sr"},
                       "a surface emitter");
  if (!ok || !shape) return std::nullopt;

  // R from the given spectrum; then total = G × integral(R), G per kind of total.
  std::vector<double> R = std::move(*shape);
  const double radiance_per_exitance = (n + 1) / (2 * kPi);  // L/R on the axis
  if (jl)
    for (double& v : R) v /= radiance_per_exitance;
  if (t) {
    if (!area_m2) return std::nullopt;  // geometry failed and was reported
    double G = 1;
    if (is_one_of(t->key, {"luminance_cd_m2", "radiance_W_m2_sr"})) G = radiance_per_exitance;
    else if (is_one_of(t->key, {"luminous_flux_lm", "radiant_flux_W"})) G = *area_m2;
    else if (is_one_of(t->key, {"luminous_intensity_cd", "radiant_intensity_W_sr"}))
      G = radiance_per_exitance * *area_m2;  // peak intensity of the whole surface, on the normal
    if (!scale_to_total(d, R, *t, G, ps)) return std::nullopt;
  }
  emission.exitance_W_m2_nm = std::move(R);
  return emission;
}

// ---- one surface ------------------------------------------------------------------------------

// The index of the surface's material; reported (with a suggestion) when it names none.
int material_of(Decoder& d, const json& j, const std::string& p) {
  const json* m = d.required(j, p, "material");
  if (!m) return 0;
  auto s = d.string(*m, p + "/material");
  if (!s) return 0;
  const std::map<std::string, int>& index = d.material_index();
  auto it = index.find(*s);
  if (it != index.end()) return it->second;
  std::string hint;
  if (d.listing()) {
    // The names as a vector, not std::views::keys: clang 14 (the fuzz build, docs/FUZZING.md) cannot
    // compile libstdc++ 12's views over a std::map. suggestion() looks at no more than these.
    std::vector<std::string_view> names;
    for (const auto& entry : index) {
      if (names.size() == kMaxSuggestionCandidates) break;
      names.push_back(entry.first);
    }
    hint = suggestion(*s, names);
  }
  d.error(p + "/material", "unknown material " + quote_text(*s) + hint);
  return 0;
}

// "role": what the surface is in a room, for the task-area summary (solver/task_summary.h).
SurfaceRole decode_role(Decoder& d, const json& j, const std::string& p) {
  const auto s = d.string(j, p);
  if (!s) return SurfaceRole::None;
  if (*s == "wall") return SurfaceRole::Wall;
  if (*s == "ceiling") return SurfaceRole::Ceiling;
  if (*s == "floor") return SurfaceRole::Floor;
  const std::vector<std::string_view> roles = {"wall", "ceiling", "floor"};
  d.error(p, "unknown role " + quote_text(*s) + " (expected wall, ceiling or floor)" + suggestion(*s, roles));
  return SurfaceRole::None;
}

void decode_surface(Decoder& d, const json& j, std::size_t i,
                    std::map<std::string, std::string>& names) {
  const std::string p = index_ptr("/surfaces", i);
  if (!d.object(j, p, {"name", "material", "polygon", "mesh", "file", "transform", "emission", "role", "thermal"}))
    return;
  Surface surface;
  surface.pointer = p;
  surface.name = d.unique_name(j, p, "surface" + std::to_string(i), names, "surface");
  surface.material = material_of(d, j, p);
  std::optional<TriangleMesh> mesh = surface_geometry(d, j, p);
  std::optional<double> area_m2;
  if (mesh) {
    area_m2 = mesh_area(*mesh);
    surface.mesh = std::move(*mesh);
  }
  if (const json* e = d.member(j, "emission")) {
    surface.emission = decode_emission(d, *e, p + "/emission", area_m2);
    // A pane has two faces (solver/pipeline/panes.h) and an emitter one front side.
    const auto& materials = d.scene().materials;
    if (static_cast<std::size_t>(surface.material) < materials.size() &&
        materials[surface.material].transmission != Transmission::kNone)
      d.error(p + "/emission", "a surface of a transmitting material (a pane) cannot emit");
  }
  if (const json* r = d.member(j, "role")) surface.role = decode_role(d, *r, p + "/role");
  if (const json* t = d.member(j, "thermal")) {
    surface.thermal = decode_thermal(d, *t, p + "/thermal");
    if (!surface.thermal) surface.thermal = SurfaceThermal{};  // reported; kept so that it is not reported missing
  }
  d.scene().surfaces.push_back(std::move(surface));
}

}  // namespace

void decode_surfaces(Decoder& d, const json& doc) {
  const json* surfaces = d.required(doc, "", "surfaces");
  if (!surfaces || !d.array(*surfaces, "/surfaces", 1)) return;
  std::map<std::string, std::string> names;  // name -> pointer of its first use
  for (std::size_t i = 0; i < surfaces->size(); ++i) decode_surface(d, (*surfaces)[i], i, names);
  check_thermal_everywhere(d);
}

}  // namespace lambert::codec
