#include "solver/lights/axial_moments.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace lambert {
namespace {

constexpr int kMaxVertices = 8;

// One edge's arc u(t) = cos t e + sin t f, t ∈ [0, θ], as the recurrence for C^k = ∫_0^θ (a·u)^k dt
// sees it: with h(t) = a·u(t) = α cos t + β sin t and h' = β cos t − α sin t,
//   C^k = (h(0)^{k−1} h'(0) − h(θ)^{k−1} h'(θ)) / k + (k−1)/k γ² C^{k−2},   γ² = α² + β² = h² + h'²,
// from d/dt (h^{k−1} h') = (k−1) γ² h^{k−2} − k h^k (the recurrence of ∫ cos^k).
struct ArcRecurrence {
  double h0 = 0, d0 = 0, h1 = 0, d1 = 0, gamma2 = 0;  // h and h' at both ends; γ²
  double am = 0, bm = 0;                              // a·m and b·m of the arc's great circle
  double c_prev = 0, c_cur = 0;                       // C^{k−1}, C^k
  double p0 = 1, p1 = 1;                              // h(0)^{k−1}, h(θ)^{k−1} for the next step

  // C^{k+1} from C^k and C^{k−1}.
  void advance(int k) {
    const int next = k + 1;
    if (next == 1) {  // C^1 = ∫ h dt = h'(0) − h'(θ)
      c_prev = c_cur;
      c_cur = d0 - d1;
      return;
    }
    p0 *= h0, p1 *= h1;
    const double c = (p0 * d0 - p1 * d1) / next + (next - 1.0) / next * gamma2 * c_prev;
    c_prev = c_cur;
    c_cur = c;
  }
};

}  // namespace

double double_axis_moment(const Point3& origin, std::span<const Point3> polygon, const Vector3& a, const Vector3& b,
                          int n) {
  const int k = static_cast<int>(std::min<std::size_t>(polygon.size(), kMaxVertices));
  std::array<Vector3, kMaxVertices> u;
  for (int i = 0; i < k; ++i) u[i] = normalize(polygon[i] - origin);
  // Signed solid angle by Van Oosterom & Strackee (1983) over the fan from u_0: tan(Ω/2) =
  // det(x, y, z) / (1 + x·y + y·z + z·x).
  double solid_angle = 0;
  for (int i = 1; i + 1 < k; ++i) {
    const Vector3 &x = u[0], &y = u[i], &z = u[i + 1];
    solid_angle += 2 * std::atan2(dot(x, cross(y, z)), 1 + dot(x, y) + dot(y, z) + dot(z, x));
  }
  const double orientation = solid_angle < 0 ? -1 : 1;
  std::array<ArcRecurrence, kMaxVertices> arcs;
  int count = 0;
  for (int i = 0; i < k; ++i) {
    const Vector3& x = u[i];
    const Vector3& y = u[(i + 1) % k];
    const Vector3 xy = cross(x, y);
    const double sine = length(xy);
    if (!(sine > 0)) continue;  // a degenerate edge spans no arc
    const double theta = std::atan2(sine, dot(x, y));
    const Vector3 m = xy * (orientation / sine);
    const Vector3 f = normalize(y - dot(x, y) * x);
    ArcRecurrence& r = arcs[count++];
    const double alpha = dot(a, x), beta = dot(a, f);
    const double c = std::cos(theta), s = std::sin(theta);
    r.h0 = alpha, r.d0 = beta;
    r.h1 = alpha * c + beta * s, r.d1 = beta * c - alpha * s;
    r.gamma2 = alpha * alpha + beta * beta;
    r.am = dot(a, m), r.bm = dot(b, m);
    r.c_cur = theta;  // C^0
  }
  // τ^{j−2}, τ^{j−1} as j runs up to n; the arcs hold C^{j−1}.
  double tau_older = 0, tau_old = std::abs(solid_angle);
  for (int j = 1; j <= n; ++j) {
    double boundary = 0;
    for (int i = 0; i < count; ++i) boundary += arcs[i].am * arcs[i].c_cur;
    const double tau = ((j - 1) * tau_older + boundary) / (j + 1);
    tau_older = tau_old, tau_old = tau;
    for (int i = 0; i < count; ++i) arcs[i].advance(j - 1);
  }
  // Now tau_old = τ^n, tau_older = τ^{n−1}, and the arcs hold C^n.
  double boundary = 0;
  for (int i = 0; i < count; ++i) boundary += arcs[i].bm * arcs[i].c_cur;
  return (n * dot(a, b) * (n >= 1 ? tau_older : 0.0) + boundary) / (n + 2);
}

}  // namespace lambert
