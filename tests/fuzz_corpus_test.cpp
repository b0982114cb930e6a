// The fuzz targets' inputs replayed in the ordinary build (tests/fuzz/, docs/FUZZING.md), through the
// same entry points the libFuzzer harnesses call (tests/fuzz/entries.h):
// - every seed under tests/fuzz/<target>/ is a valid file taken from scenes/ and tests/data/ (or the
//   same geometry written in the format's binary form), so its reader must accept it;
// - every crasher kept under tests/fuzz/regressions/<target>/ must get a clean answer: a refusal
//   that names the input, or an accepted result that keeps the reader's promises, never a crash.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/entries.h"

namespace lambert::fuzz {
namespace {

namespace fs = std::filesystem;

struct Folder {
  const char* name;
  Target target;
};
constexpr Folder kFolders[] = {{"scene", Target::kScene}, {"obj", Target::kObj}, {"ply", Target::kPly},
                               {"off", Target::kOff},     {"stl", Target::kStl}, {"vs3", Target::kVs3},
                               {"ies", Target::kIes},     {"ldt", Target::kLdt}};

Outcome run(Target target, std::string_view bytes) {
  switch (target) {
    case Target::kScene: return decode_scene_bytes(bytes);
    case Target::kVs3: return read_vs3_bytes(bytes);
    case Target::kIes:
    case Target::kLdt: return read_photometric_bytes(target, bytes);
    default: return read_mesh_bytes(target, bytes);
  }
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (fs::is_directory(dir))
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.is_regular_file()) files.push_back(entry.path());
  return files;
}

std::string bytes_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const fs::path kFuzzDir = fs::path(LAMBERT_SOURCE_DIR) / "tests" / "fuzz";

TEST(FuzzCorpus, EverySeedIsAccepted) {
  for (const Folder& folder : kFolders) {
    const std::vector<fs::path> seeds = files_in(kFuzzDir / folder.name);
    EXPECT_GE(seeds.size(), 1u) << "no seed for " << folder.name;
    for (const fs::path& seed : seeds) {
      const Outcome outcome = run(folder.target, bytes_of(seed));
      EXPECT_EQ(outcome.verdict, Verdict::kAccepted) << seed << ": " << outcome.detail;
    }
  }
}

TEST(FuzzCorpus, EveryKeptCrasherGetsACleanAnswer) {
  std::size_t replayed = 0;
  for (const Folder& folder : kFolders)
    for (const fs::path& input : files_in(kFuzzDir / "regressions" / folder.name)) {
      const Outcome outcome = run(folder.target, bytes_of(input));
      EXPECT_FALSE(is_finding(outcome)) << input << ": " << outcome.detail;
      ++replayed;
    }
  // Every folder under regressions/ names a target: an input in a misspelt one would never run.
  for (const auto& entry : fs::directory_iterator(kFuzzDir / "regressions")) {
    if (!entry.is_directory()) continue;
    bool known = false;
    for (const Folder& folder : kFolders) known = known || entry.path().filename() == folder.name;
    EXPECT_TRUE(known) << entry.path() << " is not a fuzz target's name";
  }
  RecordProperty("replayed", static_cast<int>(replayed));
}

}  // namespace
}  // namespace lambert::fuzz
