// `lambert render` (server/render.h, server/render_command.h): pixels against the radiance they must
// show, computed independently (closed forms of the light and the Phong lobe, the colour pipeline's
// own functions for the conversion to display values), the cut-away through back faces, the false
// colours and their scale, the camera syntax, and the command's files and exit codes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "tests/scene_builder.h"
#include "server/render.h"
#include "server/render_command.h"
#include "server/result_codec.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "solver/spectrum.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using test::rectangle;
using test::SceneBuilder;

std::vector<double> grid_nm() {
  std::vector<double> nm;
  for (double l = 400; l <= 700; l += 10) nm.push_back(l);
  return nm;
}

// The 8-bit value the renderer must give a linear sRGB value (white = 1), by the pipeline's encoder.
int expected_pixel(double linear) { return static_cast<int>(std::lround(255 * srgb_encode(linear))); }

// A 1 m × 1 m floor at z = 0 facing up, split into a left (x < 0) and a right half of reflectances
// rho_left and rho_right, under ambient light E: L = ρ E / π on each half.
Solution ambient_floor(SceneBuilder& b, double rho_left, double rho_right, double E) {
  const int left = b.material("left", rho_left), right = b.material("right", rho_right);
  b.surface("left", left, rectangle({-0.5, -0.5, 0}, {0.5, 0, 0}, {0, 1, 0}));
  b.surface("right", right, rectangle({0, -0.5, 0}, {0.5, 0, 0}, {0, 1, 0}));
  b.scene().lights.emplace_back(std::in_place_type<AmbientLight>, AmbientLight{std::vector<double>(b.scene().grid.size(), E)});
  b.max_patch_area(0.02);
  return solve(b.scene());
}

Camera looking_down(double height, double fov, int size) {
  Camera c;
  c.eye = {0, 0, height};
  c.look = {0, 0, 0};
  c.up = {0, 1, 0};
  c.fov_deg = fov;
  c.width = c.height = size;
  return c;
}

TEST(Render, PixelsShowThePatchRadiance) {
  SceneBuilder b(grid_nm());
  const double E = 2.0;
  const Solution sol = ambient_floor(b, 0.2, 0.8, E);
  const Report report = make_report(b.scene(), sol);
  // The radiance of each half by the closed form, through the colour pipeline.
  auto linear = [&](double rho) {
    std::vector<double> L(b.scene().grid.size(), rho * E / kPi);
    return xyz_to_linear_srgb(tristimulus(L, b.scene().grid));
  };
  const auto right = linear(0.8), left = linear(0.2);
  RenderOptions options;
  options.white_cd_m2 = 2 * tristimulus(std::vector<double>(b.scene().grid.size(), 0.8 * E / kPi), b.scene().grid).Y;
  const Image image = render(render_patches(b.scene(), sol, report), looking_down(3, 20, 101), options);
  const Rgb r = image.at(75, 50), l = image.at(25, 50);
  const int expected_r[3] = {expected_pixel(right[0] / *options.white_cd_m2), expected_pixel(right[1] / *options.white_cd_m2),
                             expected_pixel(right[2] / *options.white_cd_m2)};
  const int expected_l[3] = {expected_pixel(left[0] / *options.white_cd_m2), expected_pixel(left[1] / *options.white_cd_m2),
                             expected_pixel(left[2] / *options.white_cd_m2)};
  EXPECT_NEAR(r.r, expected_r[0], 1);
  EXPECT_NEAR(r.g, expected_r[1], 1);
  EXPECT_NEAR(r.b, expected_r[2], 1);
  EXPECT_NEAR(l.r, expected_l[0], 1);
  EXPECT_NEAR(l.g, expected_l[1], 1);
  EXPECT_NEAR(l.b, expected_l[2], 1);
  // Beyond the floor: the background.
  EXPECT_EQ(image.at(0, 0), (Rgb{32, 32, 32}));
  // Default white: the brightest patch that does not emit, i.e. the right half shows white's value.
  const Image auto_white = render(render_patches(b.scene(), sol, report), looking_down(3, 20, 101), {});
  const double Y_right = report.patches.back().luminance_cd_m2;
  EXPECT_NEAR(auto_white.at(75, 50).g, expected_pixel(right[1] / Y_right), 1);
}

TEST(Render, SmoothShadingAgreesWithTheConstantPatchesWhereTheyAgree) {
  // Uniform radiance on one surface: smooth shading shows the same value everywhere.
  SceneBuilder b(grid_nm());
  const Solution sol = ambient_floor(b, 0.5, 0.5, 1.0);
  const RenderPatches patches = render_patches(b.scene(), sol, make_report(b.scene(), sol));
  RenderOptions flat, smooth;
  smooth.smooth = true;
  const Image a = render(patches, looking_down(3, 20, 64), flat), c = render(patches, looking_down(3, 20, 64), smooth);
  for (int y = 8; y < 56; y += 7)
    for (int x = 8; x < 56; x += 7) EXPECT_EQ(a.at(x, y), c.at(x, y)) << x << ", " << y;
}

TEST(Render, ACameraOutsideAClosedRoomSeesIntoIt) {
  // A 1 m room whose walls face in; from above, the ceiling is a back face and the floor shows.
  SceneBuilder b(grid_nm());
  const int floor_material = b.material("floor", 0.8), rest = b.material("rest", 0.1);
  b.surface("floor", floor_material, rectangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  b.surface("ceiling", rest, rectangle({0, 0, 1}, {0, 1, 0}, {1, 0, 0}));
  b.scene().lights.emplace_back(std::in_place_type<AmbientLight>, AmbientLight{std::vector<double>(b.scene().grid.size(), 1.0)});
  b.max_patch_area(0.05);
  const Solution sol = solve(b.scene());
  const Report report = make_report(b.scene(), sol);
  Camera camera = looking_down(4, 10, 21);
  camera.eye = {0.5, 0.5, 4};
  camera.look = {0.5, 0.5, 0};
  const Image image = render(render_patches(b.scene(), sol, report), camera, {});
  // The floor is the brightest surface, so it sets the white: its pixel is its own radiance over its
  // own luminance (the ceiling's would be an eighth of that).
  ASSERT_EQ(sol.patches.front().surface, 0);
  const PatchPhotometry& floor_patch = report.patches.front();
  const Rgb centre = image.at(10, 10);
  EXPECT_NEAR(centre.r, expected_pixel(floor_patch.srgb[0] / floor_patch.luminance_cd_m2), 1);
  EXPECT_NEAR(centre.g, expected_pixel(floor_patch.srgb[1] / floor_patch.luminance_cd_m2), 1);
  EXPECT_NEAR(centre.b, expected_pixel(floor_patch.srgb[2] / floor_patch.luminance_cd_m2), 1);
  EXPECT_GT(centre.g, 240);
}

TEST(Render, ASheetOfTwoFacesBackToBackShowsTheFaceTowardTheCamera) {
  // A sheet (a pane, a shelf) as two coincident faces, the top ρ = 0.8 facing up, the bottom ρ = 0.2
  // facing down, triangulated along the other diagonal, over a black floor, under ambient light. The
  // two faces are at one distance along every ray, and Embree returns either; a renderer that steps
  // past the back face it returns (the bottom, from above) shows the floor through the sheet. From
  // above, every pixel on the sheet shows the top; from below, the bottom.
  SceneBuilder b(grid_nm());
  const int top = b.material("top", 0.8), bottom = b.material("bottom", 0.2), black = b.material("black", 0.0);
  b.surface("top", top, rectangle({-0.5, -0.5, 1}, {1, 0, 0}, {0, 1, 0}));
  const std::vector<Triangle> up = rectangle({-0.5, -0.5, 1}, {0, 1, 0}, {1, 0, 0});
  b.surface("bottom", bottom, {Triangle{{up[0].v[1], up[0].v[2], up[1].v[2]}}, Triangle{{up[0].v[1], up[1].v[2], up[0].v[0]}}});
  b.surface("floor", black, rectangle({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}));
  b.scene().lights.emplace_back(std::in_place_type<AmbientLight>, AmbientLight{std::vector<double>(b.scene().grid.size(), 1.0)});
  b.max_patch_area(0.01);
  const Solution sol = solve(b.scene());
  const Report report = make_report(b.scene(), sol);
  RenderOptions options;  // white: twice the top's luminance, so that both faces' pixels lie well inside 0–255
  options.white_cd_m2 = 2 * tristimulus(std::vector<double>(b.scene().grid.size(), 0.8 / kPi), b.scene().grid).Y;
  const RenderPatches patches = render_patches(b.scene(), sol, report);
  for (bool from_above : {true, false}) {
    Camera camera = looking_down(3, 14, 64);  // the sheet fills the middle of the picture
    if (!from_above) camera.eye = {0, 0, 0.5}, camera.look = {0, 0, 1}, camera.fov_deg = 100;
    const Image image = render(patches, camera, options);
    const Rgb centre = image.at(32, 32);
    int other = 0;
    for (int y = 16; y < 48; ++y)
      for (int x = 16; x < 48; ++x) other += !(image.at(x, y) == centre);
    EXPECT_EQ(other, 0) << (from_above ? "from above" : "from below");
    const double rho = from_above ? 0.8 : 0.2;  // L = ρ E / π; the floor is black
    const auto L = xyz_to_linear_srgb(tristimulus(std::vector<double>(b.scene().grid.size(), rho / kPi), b.scene().grid));
    EXPECT_NEAR(centre.g, expected_pixel(L[1] / *options.white_cd_m2), 1) << (from_above ? "from above" : "from below");
  }
}

TEST(Render, SpecularHighlightAtTheMirrorDirection) {
  // A black diffuse plane with a Phong lobe k_s = 0.5, n = 20, under an isotropic point source I at
  // height 1 straight above the origin; the camera looks straight down at the origin, along the
  // mirror direction: L = k_s (n+1)/(2π) · I/1² there (E = I cos 0 / 1²), and nothing else.
  SceneBuilder b(grid_nm());
  const int m = b.material("gloss", 0.0);
  b.scene().materials[m].specular = SpecularLobe{0.5, 20, std::vector<double>(b.scene().grid.size(), 1.0)};
  b.surface("plane", m, rectangle({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}));
  const double I = 3.0;
  b.point_light({0, 0, 1}, I);
  b.max_patch_area(0.5);
  const Solution sol = solve(b.scene());
  const Report report = make_report(b.scene(), sol);
  std::vector<double> L(b.scene().grid.size(), 0.5 * 21 / (2 * kPi) * I);
  const auto expected = xyz_to_linear_srgb(tristimulus(L, b.scene().grid));
  RenderOptions options;
  options.white_cd_m2 = 2 * tristimulus(L, b.scene().grid).Y;
  options.view_dependent = specular_shading(b.scene(), sol);
  ASSERT_TRUE(options.view_dependent);
  const Image image = render(render_patches(b.scene(), sol, report), looking_down(2, 2, 41), options);
  const Rgb centre = image.at(20, 20);
  EXPECT_NEAR(centre.r, expected_pixel(expected[0] / *options.white_cd_m2), 1);
  EXPECT_NEAR(centre.g, expected_pixel(expected[1] / *options.white_cd_m2), 1);
  EXPECT_NEAR(centre.b, expected_pixel(expected[2] / *options.white_cd_m2), 1);
  // Off the mirror direction the lobe falls off: a point x m from the origin seen from (0, 0, 2)
  // has cos α from the law of reflection; at the widest view the lobe is far down.
  const Image wide = render(render_patches(b.scene(), sol, report), looking_down(2, 60, 41), options);
  EXPECT_LT(wide.at(0, 20).g, wide.at(20, 20).g / 2);
  // Without a lobe the plane is black.
  b.scene().materials[m].specular.reset();
  EXPECT_FALSE(specular_shading(b.scene(), sol));
}

TEST(Render, FalseColoursAndTheirScale) {
  // A floor under a point source: the patch straight below is the brightest (red); the legend's bar
  // runs from dark blue at the bottom to red at the top, where legend_bar says it is.
  SceneBuilder b(grid_nm());
  b.surface("floor", b.material("grey", 0.5), rectangle({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}));
  b.point_light({0, 0, 1}, 1.0);
  b.max_patch_area(0.05);
  const Solution sol = solve(b.scene());
  const Report report = make_report(b.scene(), sol);
  const RenderPatches patches = render_patches(b.scene(), sol, report);
  for (ScaleKind kind : {ScaleKind::Log, ScaleKind::Linear}) {
    RenderOptions options;
    options.false_colour = FalseColour::Illuminance;
    options.scale = kind;
    Camera camera = looking_down(6, 30, 400);
    camera.height = 260;
    const Image image = render(patches, camera, options);
    const Rgb straight_below = image.at(camera.width / 2, camera.height / 2);
    EXPECT_GT(straight_below.r, 200);
    EXPECT_LT(straight_below.b, 60);
    const ColourScale scale = colour_scale(patches.illuminance_lx, kind);
    const LegendBar bar = legend_bar(scale, legend_title("Illuminance", "lx", kind), {camera.width - kLegendMargin, kLegendMargin},
                                     camera.height - 2 * kLegendMargin, render_legend_style());
    const int x = static_cast<int>(bar.top_left.x + bar.width / 2);
    EXPECT_EQ(image.at(x, static_cast<int>(bar.top_left.y)), false_colour_ramp(1));
    EXPECT_EQ(image.at(x, static_cast<int>(bar.top_left.y + bar.height - 1)), false_colour_ramp(0));
  }
  // A patch at a tenth of the largest illuminance: a third of the way up three decades on the log
  // scale, a tenth of the way on the linear one.
  const ColourScale log = colour_scale({1000, 100, 1}, ScaleKind::Log), linear = colour_scale({1000, 100, 1}, ScaleKind::Linear);
  EXPECT_NEAR(log.position(100), 2.0 / 3, 1e-12);
  EXPECT_NEAR(linear.position(100), 0.1, 1e-12);
}

TEST(Render, CameraSyntax) {
  const Camera c = parse_camera("eye=1,2,3 look=1,2,0;up=0,1,0 fov=30 size=320x200", Camera{});
  EXPECT_DOUBLE_EQ(c.eye.z, 3);
  EXPECT_DOUBLE_EQ(c.look.z, 0);
  EXPECT_DOUBLE_EQ(c.fov_deg, 30);
  EXPECT_EQ(c.width, 320);
  EXPECT_EQ(c.height, 200);
  const Camera kept = parse_camera("fov=50", c);  // the rest stays
  EXPECT_DOUBLE_EQ(kept.eye.y, 2);
  auto message = [](const std::string& text) {
    try {
      parse_camera(text, Camera{});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("eye=1,2").find("eye=1,2"), std::string::npos);
  EXPECT_NE(message("eye=1,2,x").find("three numbers"), std::string::npos);
  EXPECT_NE(message("fov=180").find("fov"), std::string::npos);
  EXPECT_NE(message("size=0x10").find("size"), std::string::npos);
  EXPECT_NE(message("size=10x10x").find("size"), std::string::npos);
  EXPECT_NE(message("zoom=2").find("unknown key \"zoom\""), std::string::npos);
  EXPECT_NE(message("eye=0,0,0 look=0,0,0").find("same point"), std::string::npos);
  EXPECT_NE(message("eye=0,0,1 look=0,0,0 up=0,0,1").find("parallel"), std::string::npos);
  EXPECT_NE(message("eye").find("KEY=VALUE"), std::string::npos);
  // The default camera frames the scene from −z.
  const Camera d = default_camera(rectangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0}));
  EXPECT_DOUBLE_EQ(d.look.x, 1);
  EXPECT_LT(d.eye.z, 0);
}

TEST(Render, AResultFileDrawsLikeItsSolution) {
  SceneBuilder b(grid_nm());
  const Solution sol = ambient_floor(b, 0.3, 0.6, 1.5);
  const Report report = make_report(b.scene(), sol);
  const std::string text = encode_result(b.scene(), sol, report);
  std::optional<double> white;
  const RenderPatches from_result = result_render_patches(text, white);
  ASSERT_TRUE(white);
  // The white the result's srgb_encoded implies: the brightest non-emitting patch's luminance.
  double brightest = 0;
  for (const auto& p : report.patches) brightest = std::max(brightest, p.luminance_cd_m2);
  EXPECT_NEAR(*white, brightest, 1e-3 * brightest);
  RenderOptions with_white;
  with_white.white_cd_m2 = white;
  const Image a = render(render_patches(b.scene(), sol, report), looking_down(3, 20, 64), {});
  const Image c = render(from_result, looking_down(3, 20, 64), with_white);
  for (int y = 0; y < 64; y += 5)
    for (int x = 0; x < 64; x += 5) {
      EXPECT_NEAR(a.at(x, y).r, c.at(x, y).r, 1);
      EXPECT_NEAR(a.at(x, y).g, c.at(x, y).g, 1);
    }
  EXPECT_THROW(result_render_patches("{\"patches\": [{\"vertices\": 3}]}", white), std::invalid_argument);
  EXPECT_THROW(result_render_patches("[1, 2]", white), std::invalid_argument);
}

TEST(Render, TheCommandWritesAPngAndRefusesBadUsage) {
  const fs::path dir = fs::temp_directory_path() / ("lambert_render_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path scene = dir / "scene.json", image = dir / "out.png";
  std::ofstream(scene) << R"({"lambert": 1, "spectrum": {"mode": "spectral", "wavelengths_nm": [450, 550, 650]},
    "materials": {"grey": {"reflectance": 0.5, "specular": {"coefficient": 0.2, "exponent": 30}}},
    "surfaces": [{"name": "floor", "material": "grey", "polygon": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]]}],
    "lights": [{"type": "point", "position": [0.5, 0.5, 1], "intensity": 1.0}]})";
  EXPECT_EQ(render_command({scene.string(), "-o", image.string(), "--camera", "eye=0.5,0.5,3 look=0.5,0.5,0 size=64x48"}), 0);
  EXPECT_TRUE(fs::exists(image));
  EXPECT_GT(fs::file_size(image), 100u);
  EXPECT_EQ(render_command({scene.string()}), 2);                                          // no -o
  EXPECT_EQ(render_command({scene.string(), "-o", image.string(), "--camera", "zoom=2"}), 2);
  EXPECT_EQ(render_command({scene.string(), "-o", image.string(), "--false-color", "heat"}), 2);
  EXPECT_EQ(render_command({scene.string(), "-o", image.string(), "--white", "-1"}), 2);
  EXPECT_EQ(render_command({(dir / "missing.json").string(), "-o", image.string()}), 2);
  std::ofstream(dir / "bad.json") << R"({"lambert": 1, "surfaces": 3})";
  EXPECT_EQ(render_command({(dir / "bad.json").string(), "-o", image.string()}), 2);
  EXPECT_EQ(render_command({scene.string(), "-o", (dir / "no" / "such" / "dir.png").string()}), 1);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lambert
