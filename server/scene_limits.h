// Limits on what one scene may make Lambert compute and answer (docs/SPEC.md §5, "Limits"). A
// 300-byte scene with 10 000 wavelengths made a 1.18 GB result, and 100 grid probes of 10⁶ points
// ended in std::bad_alloc (issue 37); each limit here is checked before anything of its size is
// allocated, and a scene over one is refused with a message that names it:
//   - at decode time, where the scene alone decides (probe points, their spectra, the probes' part
//     of the result): an error with the pointer of the probe or section (HTTP 422 invalid_scene);
//   - at solve time, once meshing knows (or bounds) the patch count, as a patch budget the solver
//     checks before it subdivides (SolveControl::max_patches with its reason; HTTP: the job fails
//     with the message, POST /v1/solve answers 422 solve_failed).
// `lambert serve` sets them with --max-probe-points, --max-spectral-values and --max-result-bytes,
// and so do `lambert solve` and `lambert check`; 0 turns a limit off.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lambert {

struct Scene;
struct DecodeError;

struct SceneLimits {
  std::size_t max_probe_points = 1'000'000;          // the points of every probe together
  std::size_t max_spectral_values = 100'000'000;     // wavelengths × (patches + probe points)
  std::size_t max_result_bytes = std::size_t{256} << 20;  // the result document (its upper bound)
};

// The limits' names, as messages spell them.
inline constexpr const char* kMaxProbePointsName = "max_probe_points";
inline constexpr const char* kMaxSpectralValuesName = "max_spectral_values";
inline constexpr const char* kMaxResultBytesName = "max_result_bytes";
// "NAME = VALUE, --NAME-WITH-DASHES": a limit as a message names it, with the option that sets it.
std::string limit_text(const char* name, std::size_t value);

// The decode-time checks on a scene that decoded: its probes' spectral values and its result's size
// without patches. Each problem is an error with a pointer.
std::vector<DecodeError> check_scene_limits(const Scene& scene, const SceneLimits& limits);

// The most patches the limits leave `scene` (0: no limit from them), and why, for SolveControl:
// "the 4166 patches that max_result_bytes = 268435456 allows (...)".
struct PatchBudget {
  std::size_t max_patches = 0;
  std::string reason;
};
PatchBudget patch_budget(const Scene& scene, const SceneLimits& limits);

// The tighter of a budget and a plain patch limit (0: none) named `name`.
PatchBudget tighter(PatchBudget budget, std::size_t max_patches, const std::string& name);

}  // namespace lambert
