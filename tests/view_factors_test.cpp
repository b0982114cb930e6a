// View factors between surfaces from the transport operator (solver/thermal/view_factors.h), against
// Howell's catalogue (../shared/REFERENCES.md V3, V4, V6, V8) and against reciprocity and closure.
#include <gtest/gtest.h>

#include <cmath>

#include "solver/pipeline/geometric.h"
#include "solver/thermal/view_factors.h"
#include "tests/scene_builder.h"

namespace lambert {
namespace {

using test::SceneBuilder;

ViewFactorMatrix factors_of(const Scene& scene) {
  const GeometricOperator g = build_geometric_operator(scene, {});
  return surface_view_factors(*g.op, SurfaceGroups::each_surface(scene));
}

// The unit cube seen from inside, one surface per face (test_geometry.h order: z = 0, z = 1, y = 0,
// y = 1, x = 0, x = 1).
Scene unit_cube_room(double max_patch_area) {
  SceneBuilder b;
  const int black = b.material("black", 0);
  const char* names[] = {"floor", "ceiling", "south", "north", "west", "east"};
  int k = 0;
  test::for_each_box_face(Point3{0, 0, 0}, Point3{1, 1, 1}, [&](const Point3& o, const Vector3& u, const Vector3& v) {
    b.surface(names[k++], black, test::rectangle(o, u, v));
  });
  b.max_patch_area(max_patch_area);
  return b.scene();
}

TEST(ViewFactors, UnitCubeAgainstHowellC11AndC14) {
  const ViewFactorMatrix m = factors_of(unit_cube_room(0.01));
  ASSERT_EQ(m.size(), 6u);
  const double opposite = test::howell_c11(1, 1);  // 0.1998248957, V3 X = Y = 1
  const double adjacent = test::howell_c14(1, 1);  // 0.2000437761, V4 W = H = 1
  for (std::size_t I = 0; I < 6; ++I) {
    EXPECT_NEAR(m.area_m2[I], 1.0, 1e-12);
    EXPECT_NEAR(m.row_sums[I], 1.0, 1e-12) << "closed rows: Σ_J F_IJ = 1";
    for (std::size_t J = 0; J < 6; ++J) {
      const double expected = I == J ? 0.0 : I / 2 == J / 2 ? opposite : adjacent;
      EXPECT_NEAR(m.at(I, J), expected, 1e-7) << m.names[I] << " -> " << m.names[J];
    }
  }
  EXPECT_LT(m.reciprocity_residual, 1e-14);
}

TEST(ViewFactors, TheHierarchicalOperatorSumsItsLinksToHowellsFactors) {
  // The same cube by the hierarchical method, whose links the final gather makes exact leaf by leaf
  // and whose balance closes the rows (to 1e-6) and holds each face's power: surface factors within
  // 1e-4 of Howell C-11 and C-14 (the acceptance), reciprocity within 1e-4.
  Scene scene = unit_cube_room(0.01);
  scene.solver.method = SolverMethod::Hierarchical;
  const GeometricOperator g = build_geometric_operator(scene, {});
  const ViewFactorMatrix m = surface_view_factors(*g.op, SurfaceGroups::each_surface(scene));
  ASSERT_EQ(m.size(), 6u);
  const double opposite = test::howell_c11(1, 1);  // 0.1998248957
  const double adjacent = test::howell_c14(1, 1);  // 0.2000437761
  for (std::size_t I = 0; I < 6; ++I) {
    EXPECT_NEAR(m.row_sums[I], 1.0, 1e-5) << "closed rows: Σ_J F_IJ = 1";
    for (std::size_t J = 0; J < 6; ++J) {
      const double expected = I == J ? 0.0 : I / 2 == J / 2 ? opposite : adjacent;
      EXPECT_NEAR(m.at(I, J), expected, 1e-4) << m.names[I] << " -> " << m.names[J];
    }
  }
  EXPECT_LT(m.reciprocity_residual, 1e-4);
}

// A regular n-gon of the disc's area (n/2 r'² sin(2π/n) = π r²) about c in the plane z = c.z, as a fan,
// facing +z or −z.
std::vector<Triangle> disc(const Point3& c, double r, int n, bool up) {
  const double rp = r * std::sqrt(2 * kPi / (n * std::sin(2 * kPi / n)));
  std::vector<Triangle> out;
  for (int k = 0; k < n; ++k) {
    const double a0 = 2 * kPi * k / n, a1 = 2 * kPi * (k + 1) / n;
    const Point3 p0 = c + Vector3{rp * std::cos(a0), rp * std::sin(a0), 0};
    const Point3 p1 = c + Vector3{rp * std::cos(a1), rp * std::sin(a1), 0};
    out.push_back(up ? Triangle{{c, p0, p1}} : Triangle{{c, p1, p0}});
  }
  return out;
}

TEST(ViewFactors, CoaxialDiscsAgainstHowellC41) {
  // V6: r1 = 1, r2 = 2 at h = 1 (R1 = 1, R2 = 2): F12 = (X − √(X² − 4 (R2/R1)²))/2, X = 1 + (1 + R2²)/R1²
  // = 6: F12 = 0.7639320225; F21 = F12 A1/A2 = 0.1909830056. The discs are 256-gons of the discs'
  // areas, whose factors differ from the circles' by O(n⁻²).
  SceneBuilder b;
  const int black = b.material("black", 0);
  b.surface("lower", black, disc({0, 0, 0}, 1, 256, true));
  b.surface("upper", black, disc({0, 0, 1}, 2, 256, false));
  b.max_patch_area(0.02);
  const ViewFactorMatrix m = factors_of(b.scene());
  const double X = 1 + (1 + 4.0) / 1, F12 = (X - std::sqrt(X * X - 4 * 4.0)) / 2;
  EXPECT_NEAR(F12, 0.7639320225, 1e-10);
  EXPECT_NEAR(m.at(0, 1), F12, 1e-5);
  EXPECT_NEAR(m.at(1, 0), F12 / 4, 1e-5);
  EXPECT_EQ(m.at(0, 0), 0.0);
  EXPECT_LT(m.reciprocity_residual, 1e-14);
}

TEST(ViewFactors, PerpendicularRectanglesAgainstHowellC14) {
  // V4 with W = w/l = 0.5, H = h/l = 2: a 1 × 0.5 floor strip and a 1 × 2 wall sharing the 1 m edge.
  SceneBuilder b;
  const int black = b.material("black", 0);
  b.surface("floor", black, test::rectangle({0, 0, 0}, {1, 0, 0}, {0, 0.5, 0}));
  b.surface("wall", black, test::rectangle({0, 0, 0}, {0, 0, 2}, {1, 0, 0}));
  b.max_patch_area(0.005);
  const ViewFactorMatrix m = factors_of(b.scene());
  const double F12 = test::howell_c14(0.5, 2);
  EXPECT_NEAR(m.at(0, 1), F12, 1e-6 * F12);
  EXPECT_NEAR(m.at(1, 0), F12 * 0.5 / 2, 1e-6 * F12);
  EXPECT_NEAR(m.row_sums[0], F12, 1e-6 * F12);
}

// A small sphere's share of a patch is its visible solid angle / 4π. A point at the origin under a
// 2 × 2 square at height 2 (facing down), with a 0.5 × 0.5 square at height 1 in between whose shadow is
// the central 1 × 1 (V9a's geometry): Ω = Ω(2 × 2) − Ω(1 × 1), each rectangle centred over the point,
// Ω = 4 atan(a b / (h √(a² + b² + h²))) for half-sides a, b at distance h. A plane facing up at the
// point sees V9a's visible part, 0.1659788356 (4 B-3(0.5, 0.5) − 4 B-3(0.25, 0.25)). Nothing but the
// point lies behind the blocker's plane: the point itself makes the blocker an occluder.
TEST(ViewFactors, SphereReceiverSeesTheExactVisibleSolidAngle) {
  SceneBuilder b;
  const int black = b.material("black", 0);
  b.surface("source", black, test::rectangle({-1, -1, 2}, {0, 2, 0}, {2, 0, 0}));  // facing −z
  b.surface("blocker", black, test::rectangle({-0.25, -0.25, 1}, {0.5, 0, 0}, {0, 0.5, 0}));
  b.probe("point", {0, 0, 0}, {0, 0, 1});
  for (double area : {4.0, 0.05}) {  // one patch wholly partly hidden, then many of each kind
    b.max_patch_area(area);
    const GeometricOperator g = build_geometric_operator(b.scene(), {});
    std::vector<double> source(g.op->size(), 0.0);
    for (std::size_t i = 0; i < source.size(); ++i) source[i] = g.op->patches()[i].surface == 0;
    const auto gather = g.op->point_gather({source.data()});
    double F = 0;
    gather->gather_at_point({Receiver::Kind::Spherical, {0, 0, 0}, {0, 0, 1}, {}}, &F);
    auto omega = [](double a, double h) { return 4 * std::atan(a * a / (h * std::sqrt(2 * a * a + h * h))); };
    EXPECT_NEAR(F, (omega(1, 2) - omega(0.5, 2)) / (4 * kPi), 1e-12) << "max patch area " << area;
    gather->gather_at_point({Receiver::Kind::Planar, {0, 0, 0}, {0, 0, 1}, {}}, &F);
    EXPECT_NEAR(F, 4 * test::howell_b3(0.5, 0.5) - 4 * test::howell_b3(0.25, 0.25), 1e-12);
    EXPECT_NEAR(F, 0.1659788356, 1e-10);
  }
}

}  // namespace
}  // namespace lambert
