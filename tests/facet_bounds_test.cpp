// The bounds the hierarchical refinement trusts for a cluster of triangles (solver/facet_bounds.h),
// against the triangles themselves: the area a set shows in a direction, Σ A (n·w)⁺, summed triangle
// by triangle, and whether a triangle faces a point, n·(q − p) > 0, at sampled points. Random sets
// of three kinds: normals within a cone (faceted curved surfaces), normals along the axes (buildings)
// and normals anywhere (closed objects).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "solver/facet_bounds.h"

namespace lambert {
namespace {

struct Facet {
  Triangle tri;
  Vector3 normal;
  double area;
};

enum class Kind { Cone, Axes, Anywhere };

class RandomFacets {
 public:
  explicit RandomFacets(unsigned seed) : rng_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  Vector3 direction() {
    std::normal_distribution<double> g;
    return normalize(Vector3{g(rng_), g(rng_), g(rng_)});
  }
  Point3 point_in(const Point3& c, double r) { return c + direction() * uniform(0, r); }

  // A triangle around `centre` (size up to `size`) with the given unit normal.
  Facet facet(const Point3& centre, double size, const Vector3& n) {
    const Vector3 helper = std::abs(n.x) < 0.9 ? Vector3{1, 0, 0} : Vector3{0, 1, 0};
    const Vector3 u = normalize(cross(n, helper)), v = cross(n, u);  // u × v = n
    auto corner = [&](double angle) {
      const double r = uniform(0.2, 1) * size;
      return centre + u * (r * std::cos(angle)) + v * (r * std::sin(angle));
    };
    const double a0 = uniform(0, 2.0), a1 = a0 + uniform(0.5, 2.0), a2 = a1 + uniform(0.5, 2.0);
    Facet f{Triangle{{corner(a0), corner(a1), corner(a2)}}, n, 0};
    f.area = f.tri.area();
    return f;
  }

  std::vector<Facet> set(Kind kind, int count, double spread) {
    const Vector3 axis = direction();
    const double half_angle = uniform(0.05, 1.4);
    std::vector<Facet> facets;
    for (int k = 0; k < count; ++k) {
      Vector3 n;
      switch (kind) {
        case Kind::Cone: {  // within half_angle of axis
          const Vector3 d = direction();
          const Vector3 side = normalize(d - axis * dot(d, axis));
          const double t = uniform(0, half_angle);
          n = normalize(axis * std::cos(t) + side * std::sin(t));
          break;
        }
        case Kind::Axes: {
          const int a = static_cast<int>(uniform(0, 3)) % 3;
          const double s = uniform(-1, 1) < 0 ? -1 : 1;
          n = Vector3{a == 0 ? s : 0, a == 1 ? s : 0, a == 2 ? s : 0};
          break;
        }
        case Kind::Anywhere:
          n = direction();
          break;
      }
      facets.push_back(facet(point_in({0, 0, 0}, spread), uniform(0.05, 0.5) * spread, n));
    }
    return facets;
  }

 private:
  std::mt19937 rng_;
};

FacetBounds bounds_of(const std::vector<Facet>& facets) {
  FacetBounds F;
  for (const Facet& f : facets) F.add(f.tri, f.normal, f.area);
  F.fit_cone([&](auto&& each) {
    for (const Facet& f : facets) each(f.normal);
  });
  return F;
}

double shown(const std::vector<Facet>& facets, const Vector3& w) {
  double sum = 0;
  for (const Facet& f : facets) sum += f.area * std::max(0.0, dot(f.normal, w));
  return sum;
}

// Calls check(kind, trial, facets, bounds) on `trials` random sets of each kind, of 1 to `sizes`
// triangles.
template <class Check>
void for_each_random_set(RandomFacets& random, int trials, int sizes, Check&& check) {
  for (Kind kind : {Kind::Cone, Kind::Axes, Kind::Anywhere})
    for (int trial = 0; trial < trials; ++trial) {
      const std::vector<Facet> facets = random.set(kind, 1 + trial % sizes, 1.0);
      check(kind, trial, facets, bounds_of(facets));
    }
}

TEST(FacetBounds, BinsBoundTheAreaShownAndAreExactForAxisNormals) {
  RandomFacets random(1);
  for_each_random_set(random, 100, 17, [&](Kind kind, int trial, const std::vector<Facet>& facets, const FacetBounds& F) {
    EXPECT_EQ(F.axis_normals, kind == Kind::Axes);
    for (int k = 0; k < 50; ++k) {
      const Vector3 w = random.direction();
      const double exact = shown(facets, w), binned = binned_area(F, w);
      ASSERT_GE(binned, exact * (1 - 1e-12)) << trial;
      if (kind == Kind::Axes) {
        ASSERT_NEAR(binned, exact, 1e-12 * F.area) << trial;
      }
    }
  });
}

TEST(FacetBounds, MaxProjectedBoundsEveryDirectionAndIsExactForOneTriangle) {
  RandomFacets random(2);
  for_each_random_set(random, 100, 17, [&](Kind, int trial, const std::vector<Facet>& facets, const FacetBounds& F) {
    double most = shown(facets, facets[0].normal);
    for (int k = 0; k < 400; ++k) most = std::max(most, shown(facets, random.direction()));
    ASSERT_GE(max_projected(F) * (1 + 1e-12), most) << trial;
    if (facets.size() == 1) {
      ASSERT_NEAR(max_projected(F), facets[0].area, 1e-12 * facets[0].area);
    }
  });
}

// A direction u with |u − w| = chord at most: w turned by an angle θ ≤ 2 asin(chord / 2).
Vector3 turned(RandomFacets& random, const Vector3& w, double chord) {
  const Vector3 d = random.direction();
  const Vector3 side = normalize(d - w * dot(d, w));
  const double theta = random.uniform(0, 2 * std::asin(chord / 2));
  return w * std::cos(theta) + side * std::sin(theta);
}

TEST(FacetBounds, TurningAreaBoundsWhatTheBinsGainOrLoseAlongNearbyDirections) {
  // Along every direction u within a chord s of w, the bins show binned(w) give or take
  // s × binned(w) + turning_area(w, s), and so does the set where the bins are exact (axis normals);
  // one flat piece shows A (n·w)⁺ give or take s A (n·w)⁺ + turning_area(A, n·w, s).
  RandomFacets random(6);
  for_each_random_set(random, 100, 17, [&](Kind kind, int trial, const std::vector<Facet>& facets, const FacetBounds& F) {
    for (int k = 0; k < 50; ++k) {
      const Vector3 w = random.direction();
      const double s = random.uniform(0.01, 0.8);
      const Vector3 u = turned(random, w, s);
      ASSERT_LE(length(u - w), s * (1 + 1e-12));
      const double allowed = s * binned_area(F, w) + turning_area(F, w, s) + 1e-12 * F.area;
      ASSERT_LE(std::abs(binned_area(F, u) - binned_area(F, w)), allowed) << trial;
      if (kind == Kind::Axes) {
        ASSERT_LE(std::abs(shown(facets, u) - shown(facets, w)), allowed) << trial;
      }
      for (const Facet& f : facets) {
        const double along_w = f.area * std::max(0.0, dot(f.normal, w));
        const double along_u = f.area * std::max(0.0, dot(f.normal, u));
        ASSERT_LE(std::abs(along_u - along_w), s * along_w + turning_area(f.area, dot(f.normal, w), s) + 1e-12 * f.area)
            << trial;
      }
    }
  });
}

TEST(FacetBounds, APanelSeenFromJustAboveItsPlaneMayShowItselfBelow) {
  // A 1 m² panel facing down, w 3° above its plane: the bins facing w show nothing, yet along
  // u = (cos 9°, 0, −sin 9°), 0.21 away, it shows sin 9° = 0.156 m². The relative term alone,
  // s × binned(w), is 0; turning_area counts the panel's bin whole, s × 1 m².
  const Vector3 down_normal{0, 0, -1};
  const std::vector<Facet> panel = {{Triangle{{Point3{0, 0, 0}, Point3{1, 1, 0}, Point3{1, 0, 0}}}, down_normal, 0.5},
                                    {Triangle{{Point3{0, 0, 0}, Point3{0, 1, 0}, Point3{1, 1, 0}}}, down_normal, 0.5}};
  const FacetBounds F = bounds_of(panel);
  const double degree = std::acos(-1.0) / 180, up = 3 * degree, down = 9 * degree;
  const Vector3 w{std::cos(up), 0, std::sin(up)}, u{std::cos(down), 0, -std::sin(down)};
  const double s = length(u - w);
  EXPECT_NEAR(s, 2 * std::sin(6 * degree), 1e-12);  // the chord of 12°
  EXPECT_EQ(binned_area(F, w), 0);
  EXPECT_NEAR(shown(panel, u), std::sin(down), 1e-12);
  EXPECT_NEAR(turning_area(F, w, s), s * 1.0, 1e-12);
  EXPECT_GE(turning_area(F, w, s), shown(panel, u));
}

TEST(FacetBounds, ConeHoldsEveryNormal) {
  RandomFacets random(3);
  for_each_random_set(random, 200, 9, [&](Kind, int, const std::vector<Facet>& facets, const FacetBounds& F) {
    if (F.cone_sin > 1) return;
    const double cos_theta = std::sqrt(1 - F.cone_sin * F.cone_sin);
    for (const Facet& f : facets) ASSERT_GE(dot(f.normal, F.cone_axis), cos_theta - 1e-12);
  });
  // A cone of normals within 0.5 rad of each other is found as one.
  RandomFacets narrow(4);
  int found = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<Facet> facets = narrow.set(Kind::Cone, 5, 1.0);
    found += bounds_of(facets).cone_sin <= 1;
  }
  EXPECT_EQ(found, 50);
}

// may_face(F, w, sin δ, receiver) = false promises that no triangle faces any point of the receiver,
// for receivers inside the sphere that the refinement's δ is built from. Checked at the triangles'
// corners, edge midpoints and centroids against the receiver box's corners, centre and random points.
TEST(FacetBounds, MayFaceIsFalseOnlyWhereNoTriangleFacesTheReceiver) {
  RandomFacets random(5);
  int dropped[3] = {0, 0, 0}, trials[3] = {0, 0, 0};
  for_each_random_set(random, 2000, 7, [&](Kind kind, int trial, const std::vector<Facet>& facets, const FacetBounds& F) {
    const int k = static_cast<int>(kind);
    const Point3 c_centre = F.box.center();
    const double c_radius = 0.5 * length(F.box.diagonal());
    // A receiver box of random shape (flat ones included: a receiving triangle's box).
    const Vector3 half{random.uniform(0, 0.6), random.uniform(0, 0.6), random.uniform(0, 0.6)};
    const double r_radius = length(half);
    const double d = random.uniform(1.5, 5) * (c_radius + r_radius);
    const Vector3 w = random.direction();
    const Point3 r_centre = c_centre + w * d;
    Bounds3 receiver;
    receiver.add(r_centre - half);
    receiver.add(r_centre + half);
    const double sin_delta = (c_radius + r_radius) / d;
    ++trials[k];
    if (may_face(F, w, sin_delta, receiver)) return;
    ++dropped[k];
    std::vector<Point3> q = {r_centre};
    for (int c = 0; c < 8; ++c)
      q.push_back({c & 1 ? receiver.hi.x : receiver.lo.x, c & 2 ? receiver.hi.y : receiver.lo.y,
                   c & 4 ? receiver.hi.z : receiver.lo.z});
    for (int s = 0; s < 20; ++s)
      q.push_back({random.uniform(receiver.lo.x, receiver.hi.x), random.uniform(receiver.lo.y, receiver.hi.y),
                   random.uniform(receiver.lo.z, receiver.hi.z)});
    for (const Facet& f : facets) {
      const Point3* v = f.tri.v.data();
      const Point3 p[7] = {v[0], v[1], v[2], barycentric(v[0], v[1], v[2], 0.5, 0.5, 0),
                           barycentric(v[0], v[1], v[2], 0, 0.5, 0.5), barycentric(v[0], v[1], v[2], 0.5, 0, 0.5),
                           f.tri.centroid()};
      for (const Point3& a : p)
        for (const Point3& b : q) ASSERT_LE(dot(f.normal, b - a), 1e-12 * d) << "kind " << k << " trial " << trial;
    }
  });
  // Not vacuous: sets with a cone or axis normals drop a fair share of the pairs.
  EXPECT_GT(dropped[0], trials[0] / 10);
  EXPECT_GT(dropped[1], trials[1] / 20);
  std::printf("dropped %d/%d (cone), %d/%d (axes), %d/%d (anywhere)\n", dropped[0], trials[0], dropped[1], trials[1],
              dropped[2], trials[2]);
}

TEST(FacetBounds, AnEmptySetShowsNothingAndFacesNothing) {
  FacetBounds F;
  F.fit_cone([](auto&&) {});
  EXPECT_FALSE(F.axis_normals);
  EXPECT_EQ(max_projected(F), 0);
  EXPECT_EQ(binned_area(F, Vector3{0, 0, 1}), 0);
  Bounds3 receiver;
  receiver.add({0, 0, 5});
  EXPECT_FALSE(may_face(F, Vector3{0, 0, 1}, 0.1, receiver));
}

}  // namespace
}  // namespace lambert
