// A photometric file's luminous intensity distribution I(ω) [cd], unfolded over its symmetry and
// interpolated bilinearly in the goniometer's own angles, so that it returns the file's values at
// its nodes.
//
// Every photometry type becomes a web in polar coordinates about the goniometer's polar axis: planes
// of constant azimuth φ (C for type C, H for type A, V for type B) and, in each plane, the polar
// angle θ from the axis (γ for C; V + 90° for A, from nadir; H + 90° for B, from the C90 side), with
// the measure dω = sin θ dθ dφ (photometric_data.h gives the frames). Between two planes and two
// polar angles the interpolant is bilinear in (φ, θ):
//   I(φ, θ) = Σ (1 − t)^(1−a) t^a (1 − s)^(1−b) s^b I_{k+a, j+b},   t, s the cell's fractions.
// Directions outside the web's range (above γ = 90° in a file that stops there, behind a type B
// floodlight) have I = 0, as the file says nothing of them.
//
// Integrals are exact for this interpolant: along a plane, ∫ I_k(θ) sin θ dθ over a cell where
// I_k = I_j + σ (θ − θ_j) is I_j (cos θ_j − cos θ) + σ (sin θ − sin θ_j − (θ − θ_j) cos θ), and
// across planes the interpolant is linear in φ, so the flux is Σ_k (Δφ_k / 2)(G_k + G_{k+1}) with G_k
// the plane's full integral.
#pragma once

#include <utility>
#include <vector>

#include "mesh/geometry.h"
#include "solver/photometry/photometric_data.h"

namespace lambert {

class PhotometricDistribution {
 public:
  // The web of a file the readers accepted (their checks are its preconditions: std::logic_error
  // otherwise).
  explicit PhotometricDistribution(const PhotometricData& data);

  // The goniometer's frame in the luminaire's (x the C0 direction, y C90, z up, nadir −z): the polar
  // axis, and the directions of azimuth 0 and 90° (the web's direction at (φ, θ) is
  // sin θ (cos φ zero + sin φ quarter) + cos θ polar).
  const Vector3& polar() const { return polar_; }
  const Vector3& zero() const { return zero_; }
  const Vector3& quarter() const { return quarter_; }

  // I [cd] in a unit direction of the luminaire's frame.
  double intensity(const Vector3& local_direction) const;
  // I at web coordinates (radians; φ any real, reduced here).
  double intensity_at(double phi, double theta) const;
  // ∫_{θ1}^{θ2} I(φ, θ) sin θ dθ [cd sr per radian of φ], exact for the interpolant.
  double band(double phi, double theta1, double theta2) const;
  // ∫ I dω over the sphere [lm], exact for the interpolant.
  double flux() const { return flux_; }
  // ∫ I dω over the cap θ ≤ θ_c about the polar axis [lm], exact for the interpolant (the planes'
  // integrals to θ_c, combined as flux() combines their full integrals).
  double cap_flux(double theta_c) const;
  double max_intensity() const { return max_; }
  // The azimuths of the web's planes (radians, as the web lists them) and the largest polar angle
  // with light, for the polar integral's breakpoints.
  const std::vector<double>& plane_azimuths() const { return phi_; }
  double theta_max() const { return theta_.back(); }
  // How fast I varies, relative to its peak: the largest |∂I/∂s| / I_max and |∂²I/∂s²| / I_max over
  // the web (s: arc length on the unit sphere along and across the planes; first differences of its
  // cells and second differences at its interior nodes, those across the planes from 10° off the
  // poles on), the near-field rule's measures (luminaire.h).
  // 1 and 1 for I = I_0 cos γ.
  double relative_slope() const { return slope_; }
  double relative_curvature() const { return curvature_; }

 private:
  // Plane index k and fraction t for φ, or false where φ is outside a web that is not periodic.
  bool locate_plane(double phi, std::size_t& k, double& t) const;
  double plane_value(std::size_t k, double theta) const;        // I_k(θ), 0 outside the range
  double plane_integral(std::size_t k, double theta) const;     // ∫_{θ_0}^{θ} I_k sin θ dθ
  void finish();  // prefix integrals, flux, peak and curvature

  Vector3 polar_, zero_, quarter_;
  std::vector<double> phi_;    // plane azimuths, ascending (radians)
  bool periodic_ = false;      // the planes close the circle: phi_.back() = phi_.front() + 2π
  std::vector<double> theta_;  // polar angles, ascending (radians)
  std::vector<double> I_;      // [plane][θ] cd
  std::vector<double> F_;      // [plane][θ] prefix integrals ∫_{θ_0}^{θ_j} I sin θ dθ
  double flux_ = 0, max_ = 0, slope_ = 0, curvature_ = 0;
};

// A luminaire's photometry: the file as read and its distribution, shared by every light of a scene
// that uses the file.
struct LuminairePhotometry {
  explicit LuminairePhotometry(PhotometricData data) : file(std::move(data)), distribution(file) {}
  PhotometricData file;
  PhotometricDistribution distribution;
};

}  // namespace lambert
