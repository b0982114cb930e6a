// The unfolded, interpolated intensity distribution and its exact integrals (distribution.h).
#include "solver/photometry/distribution.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "solver/spectrum.h"

namespace lambert {
namespace {

constexpr double kDegree = kPi / 180;

// The web in degrees while it is unfolded: planes (φ), polar angles (θ), values [plane][θ].
struct Web {
  std::vector<double> phi, theta, I;
  std::size_t columns() const { return theta.size(); }

  // Mirror the planes about m, which is the first (at_front) or the last azimuth: I(2m − φ) = I(φ).
  void mirror_planes(double m, bool at_front) {
    const std::size_t n = phi.size(), W = columns();
    std::vector<double> p, v;
    auto copy_plane = [&](std::size_t k) { v.insert(v.end(), I.begin() + k * W, I.begin() + (k + 1) * W); };
    if (at_front) {
      for (std::size_t k = n; k-- > 1;) p.push_back(2 * m - phi[k]), copy_plane(k);
      for (std::size_t k = 0; k < n; ++k) p.push_back(phi[k]), copy_plane(k);
    } else {
      for (std::size_t k = 0; k < n; ++k) p.push_back(phi[k]), copy_plane(k);
      for (std::size_t k = n - 1; k-- > 0;) p.push_back(2 * m - phi[k]), copy_plane(k);
    }
    phi.swap(p);
    I.swap(v);
  }
  // Mirror every plane's polar angles about the first one, m: I(2m − θ) = I(θ).
  void mirror_polar_front() {
    const std::size_t W = columns(), planes = phi.size();
    const double m = theta.front();
    std::vector<double> t, v;
    for (std::size_t j = W; j-- > 1;) t.push_back(2 * m - theta[j]);
    t.insert(t.end(), theta.begin(), theta.end());
    for (std::size_t k = 0; k < planes; ++k) {
      for (std::size_t j = W; j-- > 1;) v.push_back(I[k * W + j]);
      v.insert(v.end(), I.begin() + k * W, I.begin() + (k + 1) * W);
    }
    theta.swap(t);
    I.swap(v);
  }
};

// The file's web in the goniometer's (φ, θ), symmetry not yet unfolded.
Web web_of(const PhotometricData& d) {
  Web w;
  const std::size_t H = d.horizontal_deg.size(), V = d.vertical_deg.size();
  if (d.candela.size() != H * V) throw std::logic_error("PhotometricDistribution: table size");
  switch (d.type) {
    case PhotometryType::kC:
      w.phi = d.horizontal_deg, w.theta = d.vertical_deg, w.I = d.candela;
      break;
    case PhotometryType::kA:
      w.phi = d.horizontal_deg, w.I = d.candela;
      for (double v : d.vertical_deg) w.theta.push_back(v + 90);
      break;
    case PhotometryType::kB:  // planes are the vertical angles: transpose
      w.phi = d.vertical_deg;
      for (double h : d.horizontal_deg) w.theta.push_back(h + 90);
      w.I.resize(H * V);
      for (std::size_t h = 0; h < H; ++h)
        for (std::size_t v = 0; v < V; ++v) w.I[v * H + h] = d.candela[h * V + v];
      break;
  }
  return w;
}

// The symmetry LM-63 (and EULUMDAT, whose stored planes the reader lists the same way) states by the
// first and last angles.
void unfold(Web& w, PhotometryType type) {
  if (type == PhotometryType::kC) {
    const double first = w.phi.front(), last = w.phi.back();
    if (w.phi.size() == 1) return;  // rotational symmetry
    if (first == 0 && last == 90) w.mirror_planes(90, false), w.mirror_planes(180, false);
    else if (first == 0 && last == 180) w.mirror_planes(180, false);
    else if (first == 90 && last == 270) w.mirror_planes(90, true);
    return;
  }
  // Types A and B: an axis that starts at 0 is mirrored about 0 (the polar angle about 90°).
  if (w.phi.front() == 0) w.mirror_planes(0, true);
  if (w.theta.front() == 90) w.mirror_polar_front();
}

}  // namespace

PhotometricDistribution::PhotometricDistribution(const PhotometricData& data) {
  const Vector3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  switch (data.type) {
    case PhotometryType::kC: polar_ = -z, zero_ = x, quarter_ = y; break;
    case PhotometryType::kA: polar_ = -z, zero_ = x, quarter_ = -y; break;
    case PhotometryType::kB: polar_ = y, zero_ = -z, quarter_ = x; break;
  }
  Web w = web_of(data);
  unfold(w, data.type);
  const bool single = w.phi.size() == 1;
  const double span = w.phi.back() - w.phi.front();
  if (!single && data.type == PhotometryType::kC && span < 360) {
    // A full web that stops short of 360°: close it with the first plane (the interpolant wraps).
    w.phi.push_back(w.phi.front() + 360);
    w.I.insert(w.I.end(), w.I.begin(), w.I.begin() + static_cast<std::ptrdiff_t>(w.columns()));
  }
  periodic_ = single || w.phi.back() - w.phi.front() >= 360 - 1e-9;
  for (double p : w.phi) phi_.push_back(p * kDegree);
  for (double t : w.theta) theta_.push_back(t * kDegree);
  I_ = std::move(w.I);
  finish();
}

bool PhotometricDistribution::locate_plane(double phi, std::size_t& k, double& t) const {
  if (phi_.size() == 1) {
    k = 0, t = 0;
    return true;
  }
  const double first = phi_.front(), last = phi_.back();
  if (periodic_) {
    const double period = last - first;
    phi = first + (phi - first) - period * std::floor((phi - first) / period);
  } else {
    phi -= 2 * kPi * std::floor((phi + kPi) / (2 * kPi));  // into [−π, π)
    if (phi < first || phi > last) return false;
  }
  const auto it = std::upper_bound(phi_.begin(), phi_.end(), phi);
  k = it == phi_.begin() ? 0 : std::min<std::size_t>(static_cast<std::size_t>(it - phi_.begin()) - 1, phi_.size() - 2);
  t = std::clamp((phi - phi_[k]) / (phi_[k + 1] - phi_[k]), 0.0, 1.0);
  return true;
}

double PhotometricDistribution::plane_value(std::size_t k, double theta) const {
  if (theta < theta_.front() || theta > theta_.back()) return 0;
  const std::size_t W = theta_.size();
  const auto it = std::upper_bound(theta_.begin(), theta_.end(), theta);
  const std::size_t j = std::min<std::size_t>(static_cast<std::size_t>(it - theta_.begin()) - 1, W - 2);
  const double s = (theta - theta_[j]) / (theta_[j + 1] - theta_[j]);
  return (1 - s) * I_[k * W + j] + s * I_[k * W + j + 1];
}

double PhotometricDistribution::plane_integral(std::size_t k, double theta) const {
  const std::size_t W = theta_.size();
  if (theta <= theta_.front()) return 0;
  if (theta >= theta_.back()) return F_[k * W + W - 1];
  const auto it = std::upper_bound(theta_.begin(), theta_.end(), theta);
  const std::size_t j = static_cast<std::size_t>(it - theta_.begin()) - 1;
  const double a = theta_[j], Ia = I_[k * W + j];
  const double slope = (I_[k * W + j + 1] - Ia) / (theta_[j + 1] - a);
  const double c = std::cos(theta);
  return F_[k * W + j] + Ia * (std::cos(a) - c) + slope * (std::sin(theta) - std::sin(a) - (theta - a) * c);
}

double PhotometricDistribution::intensity_at(double phi, double theta) const {
  std::size_t k;
  double t;
  if (!locate_plane(phi, k, t)) return 0;
  if (t == 0) return plane_value(k, theta);
  return (1 - t) * plane_value(k, theta) + t * plane_value(k + 1, theta);
}

double PhotometricDistribution::intensity(const Vector3& d) const {
  const double theta = std::atan2(length(cross(d, polar_)), dot(d, polar_));
  return intensity_at(std::atan2(dot(d, quarter_), dot(d, zero_)), theta);
}

double PhotometricDistribution::band(double phi, double theta1, double theta2) const {
  if (!(theta2 > theta1)) return 0;
  std::size_t k;
  double t;
  if (!locate_plane(phi, k, t)) return 0;
  const double here = plane_integral(k, theta2) - plane_integral(k, theta1);
  if (t == 0) return here;
  return (1 - t) * here + t * (plane_integral(k + 1, theta2) - plane_integral(k + 1, theta1));
}

double PhotometricDistribution::cap_flux(double theta_c) const {
  const std::size_t P = phi_.size();
  if (P == 1) return 2 * kPi * plane_integral(0, theta_c);
  double sum = 0;
  for (std::size_t k = 0; k + 1 < P; ++k)
    sum += 0.5 * (phi_[k + 1] - phi_[k]) * (plane_integral(k, theta_c) + plane_integral(k + 1, theta_c));
  return sum;
}

void PhotometricDistribution::finish() {
  const std::size_t W = theta_.size(), P = phi_.size();
  F_.assign(P * W, 0.0);
  for (std::size_t k = 0; k < P; ++k)
    for (std::size_t j = 0; j + 1 < W; ++j) {
      // ∫ over the cell of the linear piece (distribution.h).
      const double a = theta_[j], b = theta_[j + 1], Ia = I_[k * W + j];
      const double slope = (I_[k * W + j + 1] - Ia) / (b - a);
      const double cb = std::cos(b);
      F_[k * W + j + 1] = F_[k * W + j] + Ia * (std::cos(a) - cb) + slope * (std::sin(b) - std::sin(a) - (b - a) * cb);
    }
  auto full = [&](std::size_t k) { return F_[k * W + W - 1]; };
  flux_ = 0;
  if (P == 1) flux_ = 2 * kPi * full(0);
  for (std::size_t k = 0; k + 1 < P; ++k) flux_ += 0.5 * (phi_[k + 1] - phi_[k]) * (full(k) + full(k + 1));
  max_ = I_.empty() ? 0 : *std::max_element(I_.begin(), I_.end());

  // Slopes from first differences of the cells, curvatures from second differences at interior
  // nodes (non-uniform spacing), along θ and, in arc length sin θ Δφ, across the planes.
  slope_ = curvature_ = 0;
  if (!(max_ > 0)) return;
  auto second = [](double f0, double f1, double f2, double h1, double h2) {
    return 2 * ((f2 - f1) / h2 - (f1 - f0) / h1) / (h1 + h2);
  };
  for (std::size_t k = 0; k < P; ++k)
    for (std::size_t j = 0; j + 1 < W; ++j) {
      const double h = theta_[j + 1] - theta_[j];
      slope_ = std::max(slope_, std::abs(I_[k * W + j + 1] - I_[k * W + j]) / h);
      if (j > 0)
        curvature_ = std::max(curvature_, std::abs(second(I_[k * W + j - 1], I_[k * W + j], I_[k * W + j + 1],
                                                          theta_[j] - theta_[j - 1], h)));
    }
  const std::size_t planes = periodic_ ? P - 1 : P;  // periodic: the last plane repeats the first
  for (std::size_t k = 0; P >= 2 && k + 1 < P; ++k)
    for (std::size_t j = 0; j < W; ++j) {
      const double s = std::sin(theta_[j]);
      if (!(s > 1e-12)) continue;
      const double h2 = (phi_[k + 1] - phi_[k]) * s;
      slope_ = std::max(slope_, std::abs(I_[(k + 1) * W + j] - I_[k * W + j]) / h2);
      // Near a pole the circles of latitude curve away from the great circles: there a second
      // difference across the planes measures that curvature, not I's; it is left out within 10°.
      if ((k == 0 && !periodic_) || s < std::sin(10 * kDegree)) continue;
      const std::size_t before = k == 0 ? planes - 1 : k - 1;
      const double h1 = (k == 0 ? phi_[P - 1] - phi_[P - 2] : phi_[k] - phi_[k - 1]) * s;
      curvature_ = std::max(curvature_, std::abs(second(I_[before * W + j], I_[k * W + j], I_[(k + 1) * W + j], h1, h2)));
    }
  slope_ /= max_;
  curvature_ /= max_;
}

}  // namespace lambert
