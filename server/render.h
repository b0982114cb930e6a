// Pictures of a solution (`lambert render`, SPEC §3): a pinhole camera whose primary rays Embree traces
// (solver/visibility.h); each pixel shows the radiance of the patches it sees (2 × 2 samples, averaged
// in linear light), or a false colour of their illuminance or luminance with a scale bar. Patches are
// seen from the front only: a ray passes through a back face, so a camera outside a closed room sees
// into it (a cut-away). Display: linear sRGB scaled so that a chosen luminance is white, then the sRGB
// transfer curve; values above white are clipped.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mesh/geometry.h"
#include "server/colour_scale.h"
#include "server/image.h"
#include "server/legend.h"

namespace lambert {

struct Camera {
  Point3 eye{0, 0, 1};
  Point3 look{0, 0, 0};
  Vector3 up{0, 1, 0};
  double fov_deg = 40;  // vertical field of view
  int width = 640, height = 480;
};

// Parses "eye=X,Y,Z look=X,Y,Z up=X,Y,Z fov=DEG size=WxH" (any subset, in any order, separated by
// spaces or ';'); the fields not given keep `base`'s. Throws std::invalid_argument naming the field
// and what is wrong with it (unknown key, not three numbers, fov outside (0, 180), size outside
// 1..8192, eye equal to look, up parallel to the view).
Camera parse_camera(const std::string& text, Camera base);

// The camera looking at the bounding sphere of `triangles` along +z (from −z), +y up, 40° field of
// view, far enough for the sphere to fit: the Cornell box's camera, for scenes without one.
Camera default_camera(const std::vector<Triangle>& triangles);

// What a picture is made of: triangles (in one unit, the camera's), each with the radiance it shows,
// as linear sRGB on the absolute scale (Y in cd/m²), its illuminance and luminance, and whether it
// emits (emitters do not set the white point).
struct RenderPatches {
  std::vector<Triangle> triangles;
  std::vector<std::array<double, 3>> srgb;
  std::vector<double> illuminance_lx, luminance_cd_m2;
  std::vector<char> emits;
  std::vector<int> surface;  // for smooth shading: patches of one surface share their vertices' values
};

enum class FalseColour { None, Illuminance, Luminance };

struct RenderOptions {
  FalseColour false_colour = FalseColour::None;
  ScaleKind scale = ScaleKind::Log;  // of the false colours (colour_scale.h)
  // The luminance shown as white (cd/m²); absent: the brightest patch that does not emit (the same
  // white as the result's srgb_encoded).
  std::optional<double> white_cd_m2;
  // Smooth shading: each vertex shows the area-weighted mean radiance of the patches of its surface
  // that share it, interpolated across each patch (Gouraud), instead of the patch's constant value.
  // It shows the same solution without the facets; the false colours stay per patch.
  bool smooth = false;
  // View-dependent radiance added where a patch is seen (linear sRGB, absolute): the specular lobes.
  // Arguments: the patch, the point seen, the unit direction from it towards the eye.
  std::function<std::array<double, 3>(std::size_t, const Point3&, const Vector3&)> view_dependent;
};

// Throws std::invalid_argument when there is nothing to draw (no triangles, or sizes that differ).
// With false colours, the legend (legend.h) stands at the right edge, kLegendMargin from the top,
// right and bottom.
Image render(const RenderPatches& patches, const Camera& camera, const RenderOptions& options);

// Where render() puts the false-colour legend on a picture of this size (drawn when the picture is
// at least kLegendMinWidth × kLegendMinHeight): the panel's top-right corner and height.
inline constexpr int kLegendMinWidth = 240, kLegendMinHeight = 120;
inline constexpr double kLegendMargin = 8;
LegendStyle render_legend_style();

}  // namespace lambert
