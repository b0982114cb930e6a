// `lambert viewfactors` as a user meets it (the built binary as a child process): View3D's input files
// against exact factors (Howell's catalogue, and the obstructed pair integrated here from the exact
// point factors of ../shared/REFERENCES.md V1 and V9), every output format read back by a reader of
// its own written here, and a saved factor file reused for the radiant exchange against the
// hand-solved net-radiation system.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/child_process.h"
#include "tests/net_radiation.h"
#include "tests/test_geometry.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Outcome = testing::ChildOutcome;
using TempDir = testing::ScratchDir;

std::string read_text(const fs::path& path) { return testing::read_head(path, 64 << 20); }

const fs::path kData = fs::path(LAMBERT_SOURCE_DIR) / "tests/data/view3d";

Outcome run(const std::vector<std::string>& args) { return testing::run_lambert(args); }

// `lambert viewfactors INPUT -o OUT.json` and the JSON it wrote.
json factors_json(const fs::path& input, const TempDir& dir, std::vector<std::string> extra = {}) {
  const fs::path out = dir.path() / "factors.json";
  std::vector<std::string> args = {"viewfactors", input.string(), "-o", out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const Outcome r = run(args);
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? json::parse(read_text(out)) : json();
}

double F(const json& j, std::size_t I, std::size_t J) { return j["F"][I][J].get<double>(); }

// The unit cube of View3D's manual: opposite faces C-11 (X = Y = 1), adjacent faces C-14 (W = H = 1).
TEST(ViewFactorsCli, View3dCubeAgainstHowell) {
  TempDir dir("lambert_viewfactors");
  const json j = factors_json(kData / "cube.vs3", dir);
  ASSERT_EQ(j["surfaces"].size(), 6u);
  const char* names[] = {"floor", "ceiling", "west", "east", "south", "north"};
  for (std::size_t I = 0; I < 6; ++I) {
    EXPECT_EQ(j["surfaces"][I]["name"], names[I]);
    EXPECT_NEAR(j["surfaces"][I]["area"].get<double>(), 1.0, 1e-12);
    EXPECT_EQ(j["surfaces"][I]["emissivity"].get<double>(), 0.9);
    EXPECT_NEAR(j["row_sums"][I].get<double>(), 1.0, 1e-12);
    for (std::size_t J = 0; J < 6; ++J) {
      const double expected = I == J ? 0 : I / 2 == J / 2 ? test::howell_c11(1, 1) : test::howell_c14(1, 1);
      EXPECT_NEAR(F(j, I, J), expected, 1e-6) << names[I] << " -> " << names[J];
    }
  }
  EXPECT_LT(j["reciprocity_residual"].get<double>(), 1e-12);
  EXPECT_EQ(j["geometry_hash"].get<std::string>().rfind("fnv1a64:", 0), 0u);
}

// ∫∫ over [0, 1]² by Gauss–Legendre with 24 nodes per direction (the integrands are analytic there).
template <class Integrand>
double unit_square_integral(Integrand f) {
  constexpr int n = 24;
  std::array<double, n> x{}, w{};
  for (int i = 0; i < n; ++i) {  // Newton on P_n from Chebyshev guesses
    double t = std::cos(closed_form::kPi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = t;
      for (int k = 2; k <= n; ++k) std::tie(p0, p1) = std::pair(p1, ((2 * k - 1) * t * p1 - (k - 1) * p0) / k);
      dp = n * (t * p1 - p0) / (t * t - 1);
      const double step = p1 / dp;
      t -= step;
      if (std::abs(step) < 1e-16) break;
    }
    x[i] = (1 + t) / 2;
    w[i] = 1 / ((1 - t * t) * dp * dp);  // (2 / ((1 − t²) P'²)) / 2 for [0, 1]
  }
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) sum += w[i] * w[k] * f(x[i], x[k]);
  return sum;
}

// View3D's obstructed pair: unit squares at z = 0 (facing up) and z = 1 (facing down), a 0.5 square
// [0, 0.5]² at z = 0.5 between them. From p = (x, y, 0) the square's shadow on the upper one is
// [0, 1 − x] × [0, 1 − y] (its corners 2q − p), so
//   F_lower,upper = ∫∫ F(p → upper) − F(p → [0, 1 − x] × [0, 1 − y]) dx dy          (B-3 by corners)
// and, the middle square wholly seen from the upper one, F_upper,middle = ∫∫ F(q → middle) over the
// upper square (the point 0.5 from the middle's plane).
TEST(ViewFactorsCli, View3dObstructedPairAgainstExactFactors) {
  using test::point_under_rectangle;
  const double lower_upper = unit_square_integral([](double x, double y) {
    return point_under_rectangle(x, y, 1, 0, 1, 0, 1) - point_under_rectangle(x, y, 1, 0, 1 - x, 0, 1 - y);
  });
  const double upper_middle =
      unit_square_integral([](double x, double y) { return point_under_rectangle(x, y, 0.5, 0, 0.5, 0, 0.5); });
  EXPECT_LT(lower_upper, test::howell_c11(1, 1));
  TempDir dir("lambert_viewfactors");
  for (const char* file : {"squares_obstructed.vs3", "squares_obstruction_only.vs3"}) {
    SCOPED_TRACE(file);
    const json j = factors_json(kData / file, dir);
    const bool middle_radiates = j["surfaces"].size() == 3;
    EXPECT_NEAR(F(j, 0, 1), lower_upper, 1e-4);
    EXPECT_NEAR(F(j, 1, 0), lower_upper, 1e-4);
    if (middle_radiates) {
      EXPECT_NEAR(F(j, 1, 2), upper_middle, 1e-4);
      EXPECT_NEAR(F(j, 2, 1), 4 * upper_middle, 4e-4);
      EXPECT_EQ(F(j, 0, 2), 0.0);  // the lower square sees the middle one's back
    } else {
      EXPECT_NEAR(j["to_occluders"][1].get<double>(), upper_middle, 1e-4);
    }
  }
}

// The same L-shaped room in View3D's two geometries (vertices and BLAST rectangles): the same factors,
// each floor and ceiling combined from two parts (areas added), every row closed and reciprocal.
TEST(ViewFactorsCli, View3dLRoomInBothGeometriesWithCombinations) {
  TempDir dir("lambert_viewfactors");
  const json a = factors_json(kData / "l_room_3.vs3", dir), b = factors_json(kData / "l_room_3a.vs3", dir);
  ASSERT_EQ(a["surfaces"].size(), 8u);
  ASSERT_EQ(b["surfaces"].size(), 8u);
  EXPECT_EQ(a["surfaces"][6]["name"], "floor");
  EXPECT_NEAR(a["surfaces"][6]["area"].get<double>(), 4 * 4 - 2 * 2, 1e-9);  // 4 × 2 + 2 × 2
  for (std::size_t I = 0; I < 8; ++I) {
    EXPECT_EQ(a["surfaces"][I]["name"], b["surfaces"][I]["name"]);
    EXPECT_NEAR(a["row_sums"][I].get<double>(), 1, 1e-9);
    for (std::size_t J = 0; J < 8; ++J) {
      EXPECT_NEAR(F(a, I, J), F(b, I, J), 1e-4) << I << " -> " << J;
      const double AI = a["surfaces"][I]["area"], AJ = a["surfaces"][J]["area"];
      EXPECT_NEAR(AI * F(a, I, J), AJ * F(a, J, I), 1e-12 * std::max(AI, AJ));
    }
  }
}

// Every format read back by a reader written here, against the JSON matrix: CSV triplets; View3D's
// text as View3D's ReadF0s reads it (a header line, then numbers separated by blanks: N areas, N × N
// factors, N emissivities); the EnergyPlus object split at its separators, comments dropped.
TEST(ViewFactorsCli, EveryFormatReadsBack) {
  TempDir dir("lambert_viewfactors");
  const json j = factors_json(kData / "cube.vs3", dir);
  const std::size_t S = 6;
  const fs::path csv = dir.path() / "f.csv", view3d = dir.path() / "f.vf", idf = dir.path() / "f.idf";
  const fs::path input = kData / "cube.vs3";
  ASSERT_EQ(run({"viewfactors", input.string(), "-o", csv.string()}).status, 0);
  ASSERT_EQ(run({"viewfactors", input.string(), "-o", view3d.string(), "--format", "view3d"}).status, 0);
  ASSERT_EQ(run({"viewfactors", input.string(), "-o", idf.string(), "--zone", "Cube Zone"}).status, 0);

  std::istringstream rows(read_text(csv));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "i,j,F_ij\r");
  std::size_t triplets = 0;
  while (std::getline(rows, line)) {
    std::size_t I = 0, J = 0;
    double value = 0;
    char c1 = 0, c2 = 0;
    std::istringstream(line) >> I >> c1 >> J >> c2 >> value;
    EXPECT_EQ(value, F(j, I, J)) << line;  // written to round-trip
    ++triplets;
  }
  EXPECT_EQ(triplets, S * (S - 1));  // every pair but a face with itself

  const std::string text = read_text(view3d);
  const std::string header = text.substr(0, text.find('\n'));
  EXPECT_GE(header.size(), 30u);
  std::istringstream head(header);
  std::string program, version;
  int format = -1, encl = -1, didemit = -1, n = 0;
  head >> program >> version >> format >> encl >> didemit >> n;
  EXPECT_EQ(program, "Lambert");
  EXPECT_EQ(format, 0);
  EXPECT_EQ(encl, 1);  // the file's encl=1
  EXPECT_EQ(didemit, 0);
  ASSERT_EQ(n, 6);
  std::istringstream numbers(text.substr(text.find('\n') + 1));
  std::vector<double> v;
  for (double x; numbers >> x;) v.push_back(x);
  ASSERT_EQ(v.size(), S + S * S + S);
  for (std::size_t I = 0; I < S; ++I) {
    EXPECT_NEAR(v[I], j["surfaces"][I]["area"].get<double>(), 1e-9);
    for (std::size_t J = 0; J < S; ++J) EXPECT_NEAR(v[S + I * S + J], F(j, I, J), 1e-9);
    EXPECT_EQ(v[S + S * S + I], 0.9);
  }

  std::string fields;  // the object's text without comments
  std::istringstream lines(read_text(idf));
  while (std::getline(lines, line)) fields += line.substr(0, line.find('!')) + "\n";
  std::vector<std::string> field;
  std::string current;
  for (char c : fields) {
    if (c == ',' || c == ';') {
      const std::size_t a = current.find_first_not_of(" \n"), b = current.find_last_not_of(" \n");
      field.push_back(a == std::string::npos ? "" : current.substr(a, b - a + 1));
      current.clear();
    } else {
      current += c;
    }
  }
  ASSERT_EQ(field.size(), 2 + 3 * S * S);
  EXPECT_EQ(field[0], "ZoneProperty:UserViewFactors:BySurfaceName");
  EXPECT_EQ(field[1], "Cube Zone");
  for (std::size_t k = 0; k < S * S; ++k) {
    const std::size_t I = k / S, J = k % S;
    EXPECT_EQ(field[2 + 3 * k], j["surfaces"][I]["name"]);
    EXPECT_EQ(field[3 + 3 * k], j["surfaces"][J]["name"]);
    EXPECT_NEAR(std::stod(field[4 + 3 * k]), F(j, I, J), 1e-9);
  }
}

// A factor file saved once, reused with temperatures: the net-radiation method on the surface matrix,
// against the same method hand-solved with Howell's factors (J_I − ρ_I Σ_J F_IJ J_J = ε_I σ T_I⁴,
// q_I = J_I − Σ_J F_IJ J_J), Gaussian elimination written here.
TEST(ViewFactorsCli, SavedFactorsSolveNewTemperatures) {
  TempDir dir("lambert_viewfactors");
  const fs::path saved = dir.path() / "cube.json", thermal = dir.path() / "t.json", out = dir.path() / "q.json";
  ASSERT_EQ(run({"viewfactors", (kData / "cube.vs3").string(), "-o", saved.string()}).status, 0);
  const json factors = json::parse(read_text(saved));
  const std::array<double, 6> T = {400, 300, 310, 320, 290, 300}, eps = {0.9, 0.8, 0.5, 0.9, 0.7, 0.9};
  const char* names[] = {"floor", "ceiling", "west", "east", "south", "north"};
  json t = {{"geometry_hash", factors["geometry_hash"]}, {"surfaces", json::object()}};
  for (int I = 0; I < 6; ++I) {
    t["surfaces"][names[I]] = {{"temperature_K", T[I]}};
    if (eps[I] != 0.9) t["surfaces"][names[I]]["emissivity"] = eps[I];  // else the file's 0.9
  }
  std::ofstream(thermal) << t.dump();
  const Outcome r = run({"viewfactors", saved.string(), "--thermal", thermal.string(), "-o", out.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find(" ms"), std::string::npos) << r.out;
  const json result = json::parse(read_text(out));
  auto f = [](int I, int J) { return I == J ? 0 : I / 2 == J / 2 ? test::howell_c11(1, 1) : test::howell_c14(1, 1); };
  const std::vector<double> J = test::net_radiation_radiosity(f, std::vector<double>(eps.begin(), eps.end()),
                                                              std::vector<double>(T.begin(), T.end()));
  const json& surfaces = result["thermal"]["surfaces"];
  EXPECT_EQ(result["thermal"]["level"], "surfaces");
  const double scale = test::kSigma * (std::pow(400.0, 4) - std::pow(300.0, 4));
  for (int I = 0; I < 6; ++I) {
    double H = 0;
    for (int K = 0; K < 6; ++K) H += f(I, K) * J[K];
    EXPECT_EQ(surfaces[I]["name"], names[I]);
    EXPECT_NEAR(surfaces[I]["thermal"]["radiosity_W_m2"].get<double>(), J[I], 1e-5 * scale);
    EXPECT_NEAR(surfaces[I]["thermal"]["net_flux_W_m2"].get<double>(), J[I] - H, 1e-5 * scale);
  }
  EXPECT_NEAR(result["thermal"]["balance"]["net_W"].get<double>(), 0, 1e-9 * scale);
  // Temperatures for another geometry are refused.
  t["geometry_hash"] = "fnv1a64:0000000000000000";
  std::ofstream(thermal) << t.dump();
  const Outcome wrong = run({"viewfactors", saved.string(), "--thermal", thermal.string(), "-o", out.string()});
  EXPECT_EQ(wrong.status, 2);
  EXPECT_NE(wrong.err.find("/geometry_hash"), std::string::npos) << wrong.err;
}

// The hierarchical method serves as well: its links summed to surfaces, within 1e-4 of Howell.
TEST(ViewFactorsCli, View3dCubeByTheHierarchicalMethod) {
  TempDir dir("lambert_viewfactors");
  const json j = factors_json(kData / "cube.vs3", dir, {"--method", "hierarchical"});
  ASSERT_EQ(j["surfaces"].size(), 6u);
  for (std::size_t I = 0; I < 6; ++I) {
    EXPECT_NEAR(j["row_sums"][I].get<double>(), 1.0, 1e-5);
    for (std::size_t J = 0; J < 6; ++J) {
      const double expected = I == J ? 0 : I / 2 == J / 2 ? test::howell_c11(1, 1) : test::howell_c14(1, 1);
      EXPECT_NEAR(F(j, I, J), expected, 1e-4) << I << " -> " << J;
    }
  }
}

TEST(ViewFactorsCli, BadInputIsNamed) {
  TempDir dir("lambert_viewfactors");
  const fs::path bad = dir.path() / "bad.vs3", out = dir.path() / "out.json";
  std::ofstream(bad) << "T broken\nF 3\nV 1 0 0 0\nV 2 1 0 nan\n";
  Outcome r = run({"viewfactors", bad.string(), "-o", out.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(bad.string() + ":4: vertex 2: z is not a finite number"), std::string::npos) << r.err;
  std::ofstream(bad) << "F 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\nS 1 1 2 3 4 0 0 0.9 base\n"
                        "M 2 4 3 2 1 1 0 0.9 mask\n";
  r = run({"viewfactors", bad.string(), "-o", out.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(":7: surface 2 is a mask (M)"), std::string::npos) << r.err;
  r = run({"viewfactors", (kData / "cube.vs3").string(), "-o", (dir.path() / "f.csv").string(), "--patches"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--patches"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace lambert
