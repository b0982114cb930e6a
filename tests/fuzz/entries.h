// The fuzz targets' entry points (docs/FUZZING.md): each feeds bytes to the same function the program
// calls on a file or a request body, and checks what an accepted input gives. Shared by the libFuzzer
// harnesses (fuzz_*.cpp, clang build with -DLAMBERT_FUZZ=ON) and by fuzz_corpus_test.cpp, which
// replays the committed seeds and the crashers kept under tests/fuzz/regressions/ in the normal build.
#pragma once

#include <string>
#include <string_view>

namespace lambert::fuzz {

enum class Verdict {
  kAccepted,  // the reader took the input, and what it gave holds the reader's promises
  kRefused,   // the reader refused the input with the message in `detail`
  kBroken,    // a finding: a refusal without a message, or an accepted result that breaks a promise
};

struct Outcome {
  Verdict verdict = Verdict::kBroken;
  std::string detail;
};

// The targets, by the names their corpus folders and executables carry (fuzz_<name>).
enum class Target { kScene, kObj, kPly, kOff, kStl, kVs3, kIes, kLdt };

// The name every message of a target starts with (the reader is told the input is called so).
inline constexpr std::string_view kInputName = "fuzz-input";

// decode_scene, as `lambert check` and POST /v1/solve call it, with no file access (Policy::Deny).
Outcome decode_scene_bytes(std::string_view bytes);
// parse_mesh then triangulate_polygons (read_mesh_file after its sandboxed open): kObj, kPly, kOff, kStl.
Outcome read_mesh_bytes(Target format, std::string_view bytes);
// vs3_scene, as `lambert viewfactors` reads a View3D file (the reader and the surfaces' cut-outs).
Outcome read_vs3_bytes(std::string_view bytes);
// parse_ies / parse_ldt (kIes, kLdt), as a luminaire's file or inline text is read.
Outcome read_photometric_bytes(Target format, std::string_view bytes);

// A finding when the verdict is kBroken; also when a refusal does not start with kInputName.
inline bool is_finding(const Outcome& o) {
  return o.verdict == Verdict::kBroken ||
         (o.verdict == Verdict::kRefused && o.detail.find(kInputName) == std::string::npos);
}

}  // namespace lambert::fuzz
