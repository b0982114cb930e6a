// Pictures of a solution (see render.h).
#include "server/render.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "server/export/corner_values.h"
#include "solver/spectrum.h"
#include "solver/visibility.h"

namespace lambert {
namespace {

constexpr Rgb kBackground{32, 32, 32};


Vector3 parse_triple(const std::string& key, const std::string& value) {
  double v[3];
  const char* p = value.c_str();
  for (int k = 0; k < 3; ++k) {
    char* end = nullptr;
    v[k] = std::strtod(p, &end);
    if (end == p || !std::isfinite(v[k]))
      throw std::invalid_argument("--camera " + key + "=" + value + ": expected three numbers X,Y,Z");
    p = end;
    if (k < 2) {
      if (*p != ',') throw std::invalid_argument("--camera " + key + "=" + value + ": expected three numbers X,Y,Z");
      ++p;
    }
  }
  if (*p != '\0') throw std::invalid_argument("--camera " + key + "=" + value + ": expected three numbers X,Y,Z");
  return {v[0], v[1], v[2]};
}

// Per patch, the patches that lie on it back to back (a pane's or a sheet's two faces: one plane,
// opposite normals, overlapping boxes). Along a ray both are at one distance and Embree returns
// either; where it returns the one facing away, trace() takes the one facing the camera there.
// Planes are matched by their normal and offset rounded to 1e-6 (of the scene's size for the
// offset); a pair split by the rounding is drawn as before.
std::vector<std::vector<int>> back_to_back(const std::vector<Triangle>& triangles, const std::vector<Vector3>& normals) {
  const std::size_t N = triangles.size();
  Bounds3 all;
  std::vector<Bounds3> boxes(N);
  for (std::size_t i = 0; i < N; ++i)
    for (const Point3& v : triangles[i].v) boxes[i].add(v), all.add(v);
  const double size = std::max(length(all.diagonal()), 1e-300);
  // The plane with its normal turned so that its largest component is positive, and the side.
  std::map<std::array<long long, 4>, std::array<std::vector<int>, 2>> planes;
  for (std::size_t i = 0; i < N; ++i) {
    Vector3 n = normals[i];
    const double largest = std::abs(n.x) >= std::abs(n.y) && std::abs(n.x) >= std::abs(n.z) ? n.x
                           : std::abs(n.y) >= std::abs(n.z)                                 ? n.y
                                                                                            : n.z;
    if (!std::isfinite(largest) || largest == 0) continue;
    const int side = largest > 0 ? 0 : 1;
    if (side == 1) n = n * -1.0;
    const double offset = dot(n, to_vector(triangles[i].v[0]) - to_vector(all.lo)) / size;
    const std::array<long long, 4> key = {std::llround(n.x * 1e6), std::llround(n.y * 1e6), std::llround(n.z * 1e6),
                                          std::llround(offset * 1e6)};
    planes[key][side].push_back(static_cast<int>(i));
  }
  constexpr double kMaxPairs = 4e6;  // per plane: beyond, its faces are drawn as before
  std::vector<std::vector<int>> twins(N);
  const double margin = 1e-9 * size;
  const auto overlap = [&](const Bounds3& a, const Bounds3& b) {
    for (int k = 0; k < 3; ++k)
      if (a.lo[k] > b.hi[k] + margin || b.lo[k] > a.hi[k] + margin) return false;
    return true;
  };
  for (const auto& [key, sides] : planes) {
    if (sides[0].empty() || sides[1].empty() || double(sides[0].size()) * double(sides[1].size()) > kMaxPairs) continue;
    for (int i : sides[0])
      for (int j : sides[1])
        if (overlap(boxes[i], boxes[j])) twins[i].push_back(j), twins[j].push_back(i);
  }
  return twins;
}

// Whether `point`, in the plane of t, lies in t (to 1e-9 of its size).
bool in_triangle(const Triangle& t, const Point3& point) {
  const Vector3 n = t.area_vector();
  const double whole = dot(n, n);
  if (!(whole > 0)) return false;
  for (int k = 0; k < 3; ++k) {
    const Point3 &a = t.v[(k + 1) % 3], &b = t.v[(k + 2) % 3];
    if (dot(cross(b - a, point - a), n) / whole < -1e-9) return false;
  }
  return true;
}

}  // namespace

Camera parse_camera(const std::string& text, Camera base) {
  std::string spaced = text;
  std::replace(spaced.begin(), spaced.end(), ';', ' ');
  std::istringstream in(spaced);
  std::string token;
  while (in >> token) {
    const auto eq = token.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--camera: \"" + token + "\" is not KEY=VALUE (keys: eye, look, up, fov, size)");
    const std::string key = token.substr(0, eq), value = token.substr(eq + 1);
    if (key == "eye") {
      const Vector3 v = parse_triple(key, value);
      base.eye = {v.x, v.y, v.z};
    } else if (key == "look") {
      const Vector3 v = parse_triple(key, value);
      base.look = {v.x, v.y, v.z};
    } else if (key == "up") {
      base.up = parse_triple(key, value);
    } else if (key == "fov") {
      char* end = nullptr;
      const double f = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !(f > 0 && f < 180))
        throw std::invalid_argument("--camera fov=" + value + ": expected an angle in degrees between 0 and 180");
      base.fov_deg = f;
    } else if (key == "size") {
      int w = 0, h = 0;
      char tail = 0;
      if (std::sscanf(value.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 8192 || h > 8192)
        throw std::invalid_argument("--camera size=" + value + ": expected WIDTHxHEIGHT, each 1 to 8192 pixels");
      base.width = w, base.height = h;
    } else {
      throw std::invalid_argument("--camera: unknown key \"" + key + "\" (keys: eye, look, up, fov, size)");
    }
  }
  const Vector3 view = base.look - base.eye;
  if (!(length(view) > 0)) throw std::invalid_argument("--camera: eye and look are the same point");
  if (!(length(base.up) > 0) || length(cross(normalize(view), normalize(base.up))) < 1e-9)
    throw std::invalid_argument("--camera: up is parallel to the view direction (or zero)");
  return base;
}

Camera default_camera(const std::vector<Triangle>& triangles) {
  Camera c;
  if (triangles.empty()) return c;
  Point3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity()};
  Point3 hi{-lo.x, -lo.y, -lo.z};
  for (const Triangle& t : triangles)
    for (const Point3& v : t.v) {
      lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
      hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
  const Point3 centre{(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2};
  const double radius = std::max(distance(lo, hi) / 2, 1e-12);
  const double distance_to_centre = radius / std::sin(c.fov_deg / 2 * kPi / 180);
  c.look = centre;
  c.eye = {centre.x, centre.y, centre.z - distance_to_centre};
  return c;
}

LegendStyle render_legend_style() { return {}; }

Image render(const RenderPatches& patches, const Camera& camera, const RenderOptions& options) {
  const std::size_t N = patches.triangles.size();
  if (N == 0) throw std::invalid_argument("render: there are no patches to draw");
  if (patches.srgb.size() != N || patches.illuminance_lx.size() != N || patches.luminance_cd_m2.size() != N ||
      patches.emits.size() != N)
    throw std::invalid_argument("render: the patches' attributes differ in number");
  const Visibility vis(patches.triangles);
  std::vector<Vector3> normals(N);
  for (std::size_t i = 0; i < N; ++i) normals[i] = patches.triangles[i].normal();
  const std::vector<std::vector<int>> twins = back_to_back(patches.triangles, normals);

  // Camera frame.
  const Vector3 forward = normalize(camera.look - camera.eye);
  const Vector3 right = normalize(cross(forward, camera.up));
  const Vector3 up = cross(right, forward);
  const double tan_half = std::tan(camera.fov_deg / 2 * kPi / 180);
  const double aspect = static_cast<double>(camera.width) / camera.height;
  // A segment long enough to leave the scene from the eye in any direction.
  double far = 0;
  for (const Triangle& t : patches.triangles)
    for (const Point3& v : t.v) far = std::max(far, distance(camera.eye, v));
  far = 2 * far + 1e-9;

  double white = options.white_cd_m2.value_or(0);
  if (!(white > 0)) {
    for (std::size_t i = 0; i < N; ++i)
      if (!patches.emits[i]) white = std::max(white, patches.luminance_cd_m2[i]);
    for (std::size_t i = 0; i < N && !(white > 0); ++i) white = std::max(white, patches.luminance_cd_m2[i]);
    if (!(white > 0)) white = 1;
  }
  // Smooth shading: each corner's area-weighted mean radiance over the patches of its surface that
  // meet there without a crease (corner_values.h), as the exported files carry it.
  std::vector<std::array<double, 3>> vertex_srgb;
  if (options.smooth) {
    std::vector<double> flat(3 * N);
    for (std::size_t i = 0; i < N; ++i) std::copy_n(patches.srgb[i].begin(), 3, &flat[3 * i]);
    const std::vector<double> at = corner_values(patches.triangles, patches.surface, flat, 3, Shading::Smooth);
    vertex_srgb.resize(3 * N);
    for (std::size_t c = 0; c < 3 * N; ++c) std::copy_n(&at[3 * c], 3, vertex_srgb[c].begin());
  }
  // The radiance patch i shows at `point`: its own, or interpolated from its vertices.
  auto diffuse = [&](std::size_t i, const Point3& point) {
    if (vertex_srgb.empty()) return patches.srgb[i];
    const Triangle& t = patches.triangles[i];
    const Vector3 n = t.area_vector();
    const double whole = dot(n, n);
    // Barycentric weights: the sub-triangle opposite each vertex against the whole (clamped, so a
    // point a rounding error outside gets the nearest edge's values).
    double w[3];
    for (int k = 0; k < 3; ++k) {
      const Point3 &a = t.v[(k + 1) % 3], &b = t.v[(k + 2) % 3];
      w[k] = whole > 0 ? std::clamp(dot(cross(b - a, point - a), n) / whole, 0.0, 1.0) : 1.0;
    }
    const double total = w[0] + w[1] + w[2];
    if (!(total > 0)) return patches.srgb[i];
    std::array<double, 3> out{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) out[c] += w[k] / total * vertex_srgb[3 * i + k][c];
    return out;
  };
  const std::vector<double>& shown = options.false_colour == FalseColour::Luminance ? patches.luminance_cd_m2
                                                                                   : patches.illuminance_lx;
  const ColourScale scale = colour_scale(shown, options.scale);

  // The first front face along the ray, passing through back faces: the patch and the point, or -1.
  auto trace = [&](const Vector3& dir, Point3& point) {
    Point3 from = camera.eye;
    const Point3 to = camera.eye + dir * far;
    for (int layer = 0; layer < 64; ++layer) {
      const int hit = vis.first_hit(from, to);
      if (hit < 0) return -1;
      const Vector3& n = normals[hit];
      const double along = dot(dir, n);
      const double t = along != 0 ? dot(patches.triangles[hit].v[0] - from, n) / along : 0.0;
      point = from + dir * std::max(t, 0.0);
      if (along < 0) return hit;
      for (int twin : twins[hit])  // a face lying on this back face, toward the camera
        if (in_triangle(patches.triangles[twin], point)) return twin;
      from = point + dir * (1e-6 * far);  // past the back face (Embree works in float)
    }
    return -1;
  };

  Image image(camera.width, camera.height, kBackground);
  constexpr double kSub[2] = {0.25, 0.75};  // 2 × 2 samples per pixel
  tbb::parallel_for(tbb::blocked_range<int>(0, camera.height, 4), [&](const auto& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < camera.width; ++x) {
        double sum[3] = {0, 0, 0};
        for (double sy : kSub)
          for (double sx : kSub) {
            const double u = (2 * (x + sx) / camera.width - 1) * tan_half * aspect;
            const double v = (1 - 2 * (y + sy) / camera.height) * tan_half;
            const Vector3 dir = normalize(forward + right * u + up * v);
            Point3 point;
            const int hit = trace(dir, point);
            if (hit < 0) {
              const double bg[3] = {kBackground.r / 255.0, kBackground.g / 255.0, kBackground.b / 255.0};
              for (int c = 0; c < 3; ++c) sum[c] += options.false_colour == FalseColour::None ? srgb_decode(bg[c]) : bg[c];
              continue;
            }
            if (options.false_colour != FalseColour::None) {
              const Rgb f = false_colour_ramp(scale.position(shown[hit]));
              sum[0] += f.r / 255.0, sum[1] += f.g / 255.0, sum[2] += f.b / 255.0;
              continue;
            }
            std::array<double, 3> L = diffuse(static_cast<std::size_t>(hit), point);
            if (options.view_dependent) {
              const std::array<double, 3> extra = options.view_dependent(static_cast<std::size_t>(hit), point, dir * -1.0);
              for (int c = 0; c < 3; ++c) L[c] += extra[c];
            }
            for (int c = 0; c < 3; ++c) sum[c] += L[c] / white;
          }
        Rgb out;
        std::uint8_t* channel[3] = {&out.r, &out.g, &out.b};
        for (int c = 0; c < 3; ++c) {
          const double mean = sum[c] / 4;
          const double encoded = options.false_colour == FalseColour::None ? srgb_encode(mean) : std::clamp(mean, 0.0, 1.0);
          *channel[c] = static_cast<std::uint8_t>(std::lround(255 * encoded));
        }
        image.set(x, y, out);
      }
  });

  if (options.false_colour == FalseColour::None || camera.width < kLegendMinWidth || camera.height < kLegendMinHeight)
    return image;
  const bool luminance = options.false_colour == FalseColour::Luminance;
  Canvas canvas(image);
  draw_legend(canvas, scale, legend_title(luminance ? "Luminance" : "Illuminance", luminance ? "cd/m\u00b2" : "lx", options.scale),
              {camera.width - kLegendMargin, kLegendMargin}, camera.height - 2 * kLegendMargin, render_legend_style());
  return canvas.pixels();
}

}  // namespace lambert
