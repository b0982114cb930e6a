// Photometry beyond lux: CIE S 026 melanopic quantities against the standard's own definitions,
// CIEDE2000 against the published test data, the three-sample RGB model against the properties its
// derivation promises (grey stays grey, D65 is white, luminance is preserved, a grey furnace is
// exact), and `compare-rgb` on scenes where the shortcut is exact and where it is not.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "server/compare_command.h"
#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "solver/colour_difference.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "solver/rgb_model.h"
#include "solver/spectrum.h"

namespace lambert {
namespace {

// ---- helpers -------------------------------------------------------------------------------------

std::vector<double> scaled_to_lux(const SpectrumSpec& spec, const WavelengthGrid& grid, double lux) {
  std::vector<double> s = sample_spectrum(spec, grid, SpectrumRole::Emission);
  const double k = lux / luminous_integral(s, grid);
  for (double& v : s) v *= k;
  return s;
}

Scene decode_ok(const std::string& text) {
  DecodeResult r = decode_scene(text);
  if (!r.ok()) throw std::runtime_error("scene does not decode:\n" + format_errors(r.errors));
  return std::move(*r.scene);
}

// Polygon of an axis-aligned box face, counter-clockwise seen from the inside of the box
// [0,w]×[0,h]×[0,d] (so its normal points into the room).
std::string face(const std::string& name, double w, double h, double d) {
  const std::string W = std::to_string(w), H = std::to_string(h), D = std::to_string(d);
  auto p = [](const std::string& x, const std::string& y, const std::string& z) {
    return "[" + x + "," + y + "," + z + "]";
  };
  if (name == "floor") return p("0", "0", "0") + "," + p("0", "0", D) + "," + p(W, "0", D) + "," + p(W, "0", "0");
  if (name == "ceiling") return p("0", H, "0") + "," + p(W, H, "0") + "," + p(W, H, D) + "," + p("0", H, D);
  if (name == "west") return p("0", "0", "0") + "," + p("0", H, "0") + "," + p("0", H, D) + "," + p("0", "0", D);
  if (name == "east") return p(W, "0", "0") + "," + p(W, "0", D) + "," + p(W, H, D) + "," + p(W, H, "0");
  if (name == "south") return p("0", "0", "0") + "," + p(W, "0", "0") + "," + p(W, H, "0") + "," + p("0", H, "0");
  return p("0", "0", D) + "," + p("0", H, D) + "," + p(W, H, D) + "," + p(W, "0", D);  // north
}

std::string surface(const std::string& name, const std::string& material, const std::string& polygon,
                    const std::string& extra = "") {
  return R"({"name": ")" + name + R"(", "material": ")" + material + R"(", "polygon": [)" + polygon + "]" +
         (extra.empty() ? "" : ", " + extra) + "}";
}

// CIE 15:2018 reference spectrum LED-RGB1 (mixing of red, green and blue LEDs), 5 nm, relative; the
// values of luxpy's CIE_LED_B1toB5_BH1_RGB1_V1_V2.csv (column LED-RGB1) at the 5 nm nodes 380-780.
constexpr const char* kLedRgb1 =
    R"({"nm": [380,385,390,395,400,405,410,415,420,425,430,435,440,445,450,455,460,465,470,475,480,485,
              490,495,500,505,510,515,520,525,530,535,540,545,550,555,560,565,570,575,580,585,590,595,
              600,605,610,615,620,625,630,635,640,645,650,655,660,665,670,675,680,685,690,695,700,705,
              710,715,720,725,730,735,740,745,750,755,760,765,770,775,780],
        "values": [0,0,0,0.01,0.02,0.05,0.11,0.24,0.5,0.94,1.6,2.43,3.38,4.59,5.84,5.56,4,3.14,2.8,2.68,
                   3.03,3.98,5.53,7.84,10.96,14.61,18.01,20.24,20.57,19.22,16.93,14.58,12.61,11.09,
                   9.93,9.11,8.6,8.31,8.21,8.24,8.42,8.74,9.25,10,11.1,12.74,15.35,19.43,26.01,36.47,
                   51.1,62.69,52.07,28.62,15.5,9.58,6.54,4.95,4.01,3.37,2.89,2.51,2.18,1.92,1.67,1.44,
                   1.25,1.09,0.93,0.82,0.71,0.61,0.53,0.45,0.4,0.35,0.3,0.27,0.24,0.21,0.17]})";

// ---- CIE S 026 melanopic -------------------------------------------------------------------------

TEST(Melanopic, ActionSpectrumPeaksAtOneAt490nm) {
  EXPECT_EQ(cie_s026_melanopic(490), 1.0);
  for (double nm = 380; nm <= 780; nm += 1) EXPECT_LE(cie_s026_melanopic(nm), 1.0) << nm;
  EXPECT_EQ(cie_s026_melanopic(379.5), 0.0);   // the standard defines 380-780 nm only
  EXPECT_EQ(cie_s026_melanopic(780.5), 0.0);
  EXPECT_DOUBLE_EQ(cie_s026_melanopic(380), 9.18165e-4);  // first and last rows of Table 2
  EXPECT_DOUBLE_EQ(cie_s026_melanopic(780), 2.05258e-8);
}

// K_mel,v^D65 = 1.3262 mW/lm is, by definition, E_mel of D65 per lux; so D65 at 1000 lx has
// E_mel = 1.3262 W m^-2 and a melanopic EDI of 1000 lx. Checked against the embedded table on the
// 1 nm grid of the standard and on Lambert's default 5 nm grid.
TEST(Melanopic, D65At1000LuxHasMelanopicEdiOf1000Lux) {
  for (const WavelengthGrid& grid :
       {WavelengthGrid::uniform(360, 830, 1), WavelengthGrid::uniform(380, 780, 5)}) {
    const std::vector<double> E = scaled_to_lux(CieSpectrum{CieIlluminant::D65}, grid, 1000);
    const double E_mel = melanopic_integral(E, grid);
    EXPECT_NEAR(E_mel, 1.3262, 0.005 * 1.3262) << grid.size() << " samples";
    EXPECT_NEAR(melanopic_edi_lx(E_mel), 1000, 5) << grid.size() << " samples";
  }
}

// Melanopic DER (EDI / illuminance) of CIE illuminant A: Σ s_mel S_A / (683 Σ ȳ S_A) / K_mel,v^D65
// with the tables embedded here (CIE S 026 Table 2, CIE 1931, illuminant A by its defining formula)
// gives 0.4957 (melanopic ELR of A = 0.6575 mW/lm). Checked to 1 %.
TEST(Melanopic, IlluminantADaylightEfficacyRatio) {
  const WavelengthGrid grid = WavelengthGrid::uniform(360, 830, 1);
  const std::vector<double> E = scaled_to_lux(CieSpectrum{CieIlluminant::A}, grid, 1000);
  const double der = melanopic_edi_lx(melanopic_integral(E, grid)) / 1000;
  EXPECT_NEAR(der, 0.4957, 0.01 * 0.4957);
}

// The report carries E_mel and EDI per patch, per surface (area mean) and per probe point: a floor
// under a vertical D65 beam of 1000 lx receives E_mel = 1.3262 W m^-2 (EDI 1000 lx) everywhere.
TEST(Melanopic, ReportAndResultCarryMelanopicValues) {
  const std::string text = R"({"materials": {"grey": {"reflectance": 0.5}},
    "surfaces": [)" + surface("floor", "grey", face("floor", 1, 1, 1)) + R"(],
    "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": {"cie": "D65"},
                "illuminance_lx": 1000}],
    "probes": [{"name": "desk", "position": [0.5, 0.01, 0.5], "normal": [0, 1, 0]},
               {"name": "grid", "grid": {"origin": [0.1, 0.01, 0.1], "u": [0.8, 0, 0], "v": [0, 0, 0.8],
                                         "nu": 2, "nv": 2}, "normal": [0, 1, 0]}],
    "meshing": {"max_patch_area": 0.25}})";
  const Scene scene = decode_ok(text);
  const Solution sol = solve(scene);
  const Report report = make_report(scene, sol);
  const double edi = 1000 * melanopic_integral(scaled_to_lux(CieSpectrum{CieIlluminant::D65}, scene.grid, 1), scene.grid) /
                     kMelanopicEfficacyD65_W_lm;  // the D65 DER on this grid, times 1000 lx
  for (const PatchPhotometry& p : report.patches) {
    ASSERT_TRUE(p.melanopic);
    EXPECT_NEAR(p.illuminance_lx, 1000, 1e-6);
    EXPECT_NEAR(p.melanopic->edi_lx, edi, 1e-6);
    EXPECT_NEAR(p.melanopic->irradiance_W_m2, edi * kMelanopicEfficacyD65_W_lm, 1e-9);
  }
  ASSERT_TRUE(report.surfaces.at(0).melanopic_mean);
  EXPECT_NEAR(report.surfaces[0].melanopic_mean->edi_lx, edi, 1e-6);
  ASSERT_EQ(report.probes.at(0).melanopic.size(), 1u);
  EXPECT_NEAR(report.probes[0].melanopic[0].edi_lx, edi, 1e-6);
  ASSERT_EQ(report.probes.at(1).melanopic.size(), 4u);
  for (const Melanopic& m : report.probes[1].melanopic) EXPECT_NEAR(m.edi_lx, edi, 1e-6);

  const nlohmann::json result = nlohmann::json::parse(encode_result(scene, sol, report));
  EXPECT_EQ(result.at("mode"), "spectral");
  EXPECT_NEAR(result.at("patches").at(0).at("melanopic_edi_lx").get<double>(), edi, 1e-6);
  EXPECT_NEAR(result.at("surfaces").at(0).at("melanopic_irradiance_W_m2").get<double>(),
              edi * kMelanopicEfficacyD65_W_lm, 1e-9);
  EXPECT_NEAR(result.at("probes").at(0).at("melanopic_edi_lx").get<double>(), edi, 1e-6);
  EXPECT_EQ(result.at("probes").at(1).at("melanopic_edi_lx").size(), 4u);
}

// write_result streams the patches one at a time, beside a document of the rest: its text must be
// what the whole document's dump() gives (keys sorted, "patches" in its place, the same numbers), and
// a name that needs escaping must survive.
TEST(ResultCodec, StreamedResultIsTheDocumentsDump) {
  const std::string text = R"({"name": "r\u00e9sultat \"q\"", "materials": {"grey": {"reflectance": 0.5}},
    "surfaces": [)" + surface(R"(floor \\ \"A\")", "grey", face("floor", 1, 1, 1)) + R"(],
    "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": {"cie": "D65"},
                "illuminance_lx": 1000}],
    "probes": [{"name": "desk", "position": [0.5, 0.01, 0.5], "normal": [0, 1, 0]}],
    "meshing": {"max_patch_area": 0.25}})";
  const Scene scene = decode_ok(text);
  const Solution sol = solve(scene);
  const Report report = make_report(scene, sol);
  const std::string out = encode_result(scene, sol, report);
  const nlohmann::json result = nlohmann::json::parse(out);
  EXPECT_EQ(result.dump(), out);
  ASSERT_EQ(result.at("patches").size(), sol.patches.size());
  ASSERT_GE(sol.patches.size(), 4u);
  for (std::size_t i = 0; i < sol.patches.size(); ++i) {
    EXPECT_EQ(result["patches"][i].at("id"), i);
    EXPECT_EQ(result["patches"][i].at("surface"), R"(floor \ "A")");
    EXPECT_EQ(result["patches"][i].at("radiosity").size(), scene.grid.size());
  }
  EXPECT_EQ(result.at("name"), "r\u00e9sultat \"q\"");
  EXPECT_EQ(result.at("probes").size(), 1u);
}

// ---- CIELAB and CIEDE2000 ------------------------------------------------------------------------

TEST(Cielab, WhiteIsL100AndNeutral) {
  const Xyz white = white_from_chromaticity(80, 0.3127, 0.3290);
  const Lab w = cielab(white, white);
  EXPECT_NEAR(w.L, 100, 1e-12);
  EXPECT_NEAR(w.a, 0, 1e-12);
  EXPECT_NEAR(w.b, 0, 1e-12);
  // Y/Yn = 0.18 (a mid grey): L* = 116 · 0.18^(1/3) − 16 = 49.4961.
  EXPECT_NEAR(cielab({white.X * 0.18, white.Y * 0.18, white.Z * 0.18}, white).L, 49.4961, 1e-4);
  // Below (6/29)^3 the linear segment: Y/Yn = 0.001 gives L* = 903.2963 · 0.001 = 0.9033.
  EXPECT_NEAR(cielab({white.X * 0.001, white.Y * 0.001, white.Z * 0.001}, white).L, 0.903296, 1e-6);
}

// G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 color-difference formula: implementation notes,
// supplementary test data, and mathematical observations", Color Res. Appl. 30(1):21-30, 2005,
// Table 1: all 34 pairs {L1, a1, b1, L2, a2, b2, ΔE00}. Numbers as in the public copy
// beku/Argyll-Releases, icc/testDE2K.c, commit b3598744f924307d7fbc9f22e21c5a6c83160f82.
constexpr double kSharmaPairs[34][7] = {
    {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
    {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
    {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
    {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
    {50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461},
    {50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065},
    {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
    {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
    {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
    {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000},
    {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
    {63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630},
    {61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731},
    {35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645},
    {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373},
    {36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146},
    {90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441},
    {90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381},
    {6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377},
    {2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082},
};

TEST(Ciede2000, SharmaWuDalalTestData) {
  for (int k = 0; k < 34; ++k) {
    const double* r = kSharmaPairs[k];
    const Lab first{r[0], r[1], r[2]}, second{r[3], r[4], r[5]};
    EXPECT_NEAR(ciede2000(first, second), r[6], 1e-4) << "pair " << k + 1;
    EXPECT_NEAR(ciede2000(second, first), r[6], 1e-4) << "pair " << k + 1 << " reversed";
  }
}

TEST(Ciede2000, ZeroForEqualColours) {
  EXPECT_EQ(ciede2000({50, 10, -20}, {50, 10, -20}), 0.0);
  EXPECT_EQ(ciede2000({0, 0, 0}, {0, 0, 0}), 0.0);
}

// ---- The RGB model -------------------------------------------------------------------------------

TEST(RgbModel, ChannelGridCarriesLuminanceWeightsAndDominantWavelengths) {
  const WavelengthGrid g = rgb_channel_grid();
  ASSERT_EQ(g.size(), 3u);
  // The middle row of the EBU RGB -> XYZ matrix (SMPTE RP 177 from the EBU Tech 3213 primaries).
  EXPECT_NEAR(g.weight_nm[0], 0.2220, 5e-5);
  EXPECT_NEAR(g.weight_nm[1], 0.7067, 5e-5);
  EXPECT_NEAR(g.weight_nm[2], 0.0713, 5e-5);
  EXPECT_NEAR(g.weight_nm[0] + g.weight_nm[1] + g.weight_nm[2], 1.0, 1e-12);  // white has Y = 1
  // Dominant wavelengths of the EBU primaries relative to D65 (red ~611, green ~549, blue ~465 nm).
  EXPECT_GT(g.nm[0], 600);
  EXPECT_LT(g.nm[0], 620);
  EXPECT_GT(g.nm[1], 540);
  EXPECT_LT(g.nm[1], 560);
  EXPECT_GT(g.nm[2], 455);
  EXPECT_LT(g.nm[2], 475);
}

TEST(RgbModel, GreyReflectanceStaysGreyAndOneIsExactlyOne) {
  const WavelengthGrid fine = rgb_reduction_grid();
  for (double beta : {0.0, 0.05, 0.3, 0.75}) {
    const std::array<double, 3> O = rgb_object_reflectance(std::vector<double>(fine.size(), beta), fine);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(O[c], beta, 1e-14) << "beta " << beta << " channel " << c;
  }
  const std::array<double, 3> one = rgb_object_reflectance(std::vector<double>(fine.size(), 1.0), fine);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(one[c], 1.0);
}

// D65 is the white of the EBU matrix: its three channel values are equal (to the difference between
// the D65 table's chromaticity, 0.31272/0.32903, and the 4-digit white 0.3127/0.3290 of the matrix),
// and the luminance computed from the channels equals the spectral luminance.
TEST(RgbModel, D65SourceIsWhiteBalancedAndKeepsItsLuminance) {
  const WavelengthGrid fine = rgb_reduction_grid();
  const std::vector<double> S = scaled_to_lux(CieSpectrum{CieIlluminant::D65}, fine, 1000);
  const std::array<double, 3> I = rgb_source_values(S, fine);
  EXPECT_NEAR(I[0] / I[1], 1, 1e-3);
  EXPECT_NEAR(I[2] / I[1], 1, 1e-3);
  EXPECT_NEAR(xyz_from_rgb_channels(I).Y, luminous_integral(S, fine), 1e-12 * 1000);
  const Xyz spectral = tristimulus(S, fine), channels = xyz_from_rgb_channels(I);
  EXPECT_NEAR(channels.X, spectral.X, 1e-12 * 1000);
  EXPECT_NEAR(channels.Z, spectral.Z, 1e-12 * 1000);
}

// Any source: 683 (0.2220 R + 0.7067 G + 0.0713 B) is its luminous value, because the value curves
// are a linear transform of the CMFs.
TEST(RgbModel, ChannelsPreserveTheLuminanceOfAnySource) {
  const WavelengthGrid fine = rgb_reduction_grid();
  for (const SpectrumSpec& spec : std::vector<SpectrumSpec>{
           CieSpectrum{CieIlluminant::A}, BlackbodySpectrum{5000},
           TabulatedSpectrum{{580, 589, 598}, {0, 1, 0}}}) {
    const std::vector<double> S = scaled_to_lux(spec, fine, 500);
    EXPECT_NEAR(xyz_from_rgb_channels(rgb_source_values(S, fine)).Y, 500, 1e-9);
  }
}

// Decoding "mode": "rgb": materials and sources become three channels; a saturated reflectance
// whose O_c leaves [0, 1] and a narrow-band source outside the EBU gamut are kept as computed and
// reported in the warnings with their amounts.
TEST(RgbModel, DecoderReducesTheSceneAndWarnsOutsideTheRange) {
  const std::string text = R"({"spectrum": {"mode": "rgb"},
    "materials": {"grey": {"reflectance": 0.4},
                  "deep red": {"reflectance": {"nm": [560, 600], "values": [0, 1]}}},
    "surfaces": [)" + surface("floor", "grey", face("floor", 1, 1, 1)) + "," +
                           surface("wall", "deep red", face("west", 1, 1, 1)) + R"(],
    "lights": [{"type": "point", "position": [0.5, 0.9, 0.5],
                "intensity": {"nm": [580, 589, 598], "values": [0, 1, 0]}, "luminous_intensity_cd": 100}]})";
  const Scene scene = decode_ok(text);
  EXPECT_EQ(scene.mode, SpectrumMode::Rgb);
  ASSERT_EQ(scene.grid.size(), 3u);
  ASSERT_EQ(scene.materials.size(), 2u);
  const Material& grey = scene.materials[0].name == "grey" ? scene.materials[0] : scene.materials[1];
  const Material& red = scene.materials[0].name == "grey" ? scene.materials[1] : scene.materials[0];
  for (double o : grey.reflectance) EXPECT_NEAR(o, 0.4, 1e-14);
  EXPECT_GT(red.reflectance[0], 1.0);  // β = 1 where r̄ > 0, 0 under most of its negative lobe
  const PointLight& light = std::get<PointLight>(scene.lights.at(0));
  ASSERT_EQ(light.intensity_W_sr_nm.size(), 3u);
  EXPECT_LT(light.intensity_W_sr_nm[2], 0.0);  // 589 nm lies outside the EBU triangle: B < 0
  EXPECT_NEAR(xyz_from_rgb_channels({light.intensity_W_sr_nm[0], light.intensity_W_sr_nm[1],
                                     light.intensity_W_sr_nm[2]}).Y, 100, 1e-9);
  bool warned_reflectance = false, warned_source = false;
  for (const std::string& w : scene.warnings) {
    warned_reflectance |= w.find("/materials/deep red/reflectance") == 0 && w.find("O_R") != std::string::npos &&
                          w.find("above 1 by") != std::string::npos;
    warned_source |= w.find("/lights/0") == 0 && w.find("outside the EBU gamut") != std::string::npos &&
                     w.find("I_B") != std::string::npos;
  }
  EXPECT_TRUE(warned_reflectance) << testing::PrintToString(scene.warnings);
  EXPECT_TRUE(warned_source) << testing::PrintToString(scene.warnings);
}

// A closed box with every wall grey (ρ = 0.6) and emitting M = 100 lm/m² of D65 light: B = M/(1 − ρ)
// everywhere (the furnace), so L = 100 / (0.4 π) cd/m². The spectral and the rgb solves agree to 1e-6:
// a grey world is exactly what the three-sample model represents.
TEST(RgbModel, GreyFurnaceMatchesTheSpectralSolve) {
  std::string surfaces;
  for (const char* f : {"floor", "ceiling", "west", "east", "south", "north"}) {
    if (!surfaces.empty()) surfaces += ",";
    surfaces += surface(f, "grey", face(f, 1, 1, 1),
                        R"("emission": {"exitance": {"cie": "D65"}, "luminous_exitance_lm_m2": 100})");
  }
  const std::string body = R"("materials": {"grey": {"reflectance": 0.6}}, "surfaces": [)" + surfaces +
                           R"(], "meshing": {"max_patch_area": 0.05}, "solver": {"tolerance": 1e-9}})";
  const Scene spectral = decode_ok("{" + body);
  const Scene rgb = decode_ok(R"({"spectrum": {"mode": "rgb"}, )" + body);
  const Solution sol_s = solve(spectral), sol_r = solve(rgb);
  const Report rep_s = make_report(spectral, sol_s), rep_r = make_report(rgb, sol_r);
  ASSERT_EQ(rep_s.patches.size(), rep_r.patches.size());
  const double closed_form = 100 / (0.4 * kPi);
  for (std::size_t i = 0; i < rep_s.patches.size(); ++i) {
    EXPECT_NEAR(rep_r.patches[i].luminance_cd_m2, rep_s.patches[i].luminance_cd_m2,
                1e-6 * rep_s.patches[i].luminance_cd_m2) << i;
    EXPECT_NEAR(rep_r.patches[i].luminance_cd_m2, closed_form, 1e-3 * closed_form) << i;
    EXPECT_NEAR(rep_r.patches[i].illuminance_lx, rep_s.patches[i].illuminance_lx,
                1e-6 * rep_s.patches[i].illuminance_lx) << i;
  }
  EXPECT_FALSE(rep_r.patches[0].melanopic);  // three samples do not determine E_mel
  const nlohmann::json result = nlohmann::json::parse(encode_result(rgb, sol_r, rep_r));
  EXPECT_EQ(result.at("mode"), "rgb");
  EXPECT_EQ(result.at("channels"), nlohmann::json::array({"R", "G", "B"}));
  EXPECT_FALSE(result.contains("wavelengths_nm"));
  EXPECT_EQ(result.at("patches").at(0).at("radiosity").size(), 3u);
}

// ---- compare-rgb ---------------------------------------------------------------------------------

// A 2 × 2 × 2 m room lit from a point light with the LED-RGB1 spectrum; walls `wall_a` and `wall_b`.
std::string led_room(const std::string& materials, const std::string& wall_a, const std::string& wall_b) {
  std::string surfaces = surface("floor", "floor", face("floor", 2, 2, 2)) + "," +
                         surface("ceiling", "floor", face("ceiling", 2, 2, 2)) + "," +
                         surface("west", wall_a, face("west", 2, 2, 2)) + "," +
                         surface("east", wall_b, face("east", 2, 2, 2)) + "," +
                         surface("south", wall_a, face("south", 2, 2, 2)) + "," +
                         surface("north", wall_b, face("north", 2, 2, 2));
  return R"({"name": "led-room", "materials": {)" + materials + R"(}, "surfaces": [)" + surfaces + R"(],
    "lights": [{"type": "point", "position": [1, 1.9, 1], "intensity": )" + kLedRgb1 + R"(,
                "luminous_flux_lm": 1000}],
    "meshing": {"max_patch_area": 0.25}})";
}

RgbComparison compare_text(const std::string& text) {
  const Scene spectral = decode_ok(text);
  DecodeResult rgb = decode_scene_as_rgb(text);
  if (!rgb.ok()) throw std::runtime_error(format_errors(rgb.errors));
  return compare_rgb(spectral, *rgb.scene);
}

// Grey walls: every patch's spectrum is the source spectrum times a number, which three channels
// represent exactly; the colour difference is zero up to the quadrature of the two grids.
TEST(CompareRgb, GreySceneHasNoColourDifference) {
  const RgbComparison c =
      compare_text(led_room(R"("floor": {"reflectance": 0.5}, "a": {"reflectance": 0.7}, "b": {"reflectance": 0.3})",
                            "a", "b"));
  EXPECT_GT(c.delta_e00.count, 0u);
  EXPECT_LT(c.delta_e00.max, 0.05);
  EXPECT_LT(c.illuminance_relative.max, 1e-3);
}

// Saturated ColorChecker red and cyan walls (tabulated reflectances) under the three-peak LED: the
// channel reflectances, fixed under D65, no longer describe what these walls reflect of this light,
// and the error grows with each bounce.
TEST(CompareRgb, SaturatedSceneShowsColourDifferences) {
  const std::string materials = R"("floor": {"reflectance": 0.5},
    "red":  {"reflectance": {"nm": [400,450,500,550,575,600,625,650,700],
                             "values": [0.051,0.049,0.044,0.047,0.063,0.192,0.550,0.686,0.729]}},
    "cyan": {"reflectance": {"nm": [400,450,480,500,550,600,650,700],
                             "values": [0.195,0.352,0.458,0.433,0.180,0.080,0.074,0.072]}})";
  const std::string text = led_room(materials, "red", "cyan");
  const RgbComparison c = compare_text(text);
  EXPECT_GT(c.delta_e00.mean, 1.0);
  EXPECT_GT(c.delta_e00.max, 2.0);
  EXPECT_GE(c.delta_e00.p95, c.delta_e00.median);
  EXPECT_GE(c.delta_e00.max, c.delta_e00.p95);
  ASSERT_FALSE(c.worst.empty());
  EXPECT_EQ(c.patches[c.worst[0]].delta_e00, c.delta_e00.max);
  // Reproducible: the same report, byte for byte, on a second run.
  const Scene spectral = decode_ok(text);
  EXPECT_EQ(encode_comparison(spectral, c), encode_comparison(spectral, compare_text(text)));
}

}  // namespace
}  // namespace lambert
