// Photometric files (tests/fuzz/entries.h): parse_ies and parse_ldt, the functions a luminaire's
// file or inline text is read with.
#include <cmath>
#include <string>

#include "solver/photometry/photometric_data.h"
#include "tests/fuzz/entries.h"

namespace lambert::fuzz {

namespace {

// What photometric_data.h promises of an accepted file: a table of horizontal × vertical candela
// values within the limits, every value a finite non-negative number, angles finite and ascending.
std::string broken_promise(const PhotometricData& d) {
  const PhotometricLimits limits;
  const std::size_t nv = d.vertical_deg.size(), nh = d.horizontal_deg.size();
  if (nv == 0 || nh == 0) return "accepted without angles";
  if (nv > limits.max_vertical_angles || nh > limits.max_horizontal_angles) return "accepted beyond the angle limits";
  if (d.candela.size() != nv * nh)
    return "candela has " + std::to_string(d.candela.size()) + " values for " + std::to_string(nh) + " × " +
           std::to_string(nv) + " angles";
  for (double c : d.candela)
    if (!std::isfinite(c) || c < 0) return "accepted a candela value that is negative or not finite";
  for (const auto* angles : {&d.vertical_deg, &d.horizontal_deg})
    for (std::size_t i = 0; i < angles->size(); ++i) {
      if (!std::isfinite((*angles)[i])) return "accepted an angle that is not finite";
      if (i > 0 && !((*angles)[i] > (*angles)[i - 1])) return "accepted angles out of order";
    }
  return {};
}

}  // namespace

Outcome read_photometric_bytes(Target format, std::string_view bytes) {
  const PhotometricParse parse =
      format == Target::kLdt ? parse_ldt(bytes, kInputName) : parse_ies(bytes, kInputName);
  if (!parse.ok()) return {Verdict::kRefused, parse.error};
  std::string broken = broken_promise(*parse.data);
  if (!broken.empty()) return {Verdict::kBroken, std::move(broken)};
  return {Verdict::kAccepted, {}};
}

}  // namespace lambert::fuzz
