// One libFuzzer harness for every target (docs/FUZZING.md): CMake builds it once per target, with
// LAMBERT_FUZZ_TARGET the Target's enumerator and LAMBERT_FUZZ_FAMILY_* naming the entry file it links,
// so that a reader's target links only that reader. A finding (entries.h) aborts with its detail, and
// libFuzzer keeps the input as crash-*; a sanitizer report or an escaping exception does the same.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "tests/fuzz/entries.h"

using lambert::fuzz::Target;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
#if defined(LAMBERT_FUZZ_FAMILY_MESH)
  const lambert::fuzz::Outcome outcome = lambert::fuzz::read_mesh_bytes(Target::LAMBERT_FUZZ_TARGET, bytes);
#elif defined(LAMBERT_FUZZ_FAMILY_PHOTOMETRY)
  const lambert::fuzz::Outcome outcome = lambert::fuzz::read_photometric_bytes(Target::LAMBERT_FUZZ_TARGET, bytes);
#elif defined(LAMBERT_FUZZ_FAMILY_VS3)
  const lambert::fuzz::Outcome outcome = lambert::fuzz::read_vs3_bytes(bytes);
#else
  const lambert::fuzz::Outcome outcome = lambert::fuzz::decode_scene_bytes(bytes);
#endif
  if (lambert::fuzz::is_finding(outcome)) {
    std::fprintf(stderr, "finding: %s\n", outcome.detail.empty() ? "a refusal without a message" : outcome.detail.c_str());
    std::abort();
  }
  return 0;
}
