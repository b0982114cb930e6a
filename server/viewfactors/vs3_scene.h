// A View3D input file (.vs3, mesh/vs3_reader.h) as a Lambert scene, so that a user's file runs
// unchanged (View3D's manual, "Input File Format"):
// - radiating surfaces (S) are the reported surfaces, in file order, with their names; a combination
//   number merges a surface into the earlier one it names (one reported surface, its parts' areas
//   added);
// - a subsurface (S with a base: a window in a wall) is cut out of its base, so the base reports what
//   is left of it (View3D's "separate"); a subsurface of an obstruction radiates from inside it;
// - a null surface (N) is cut out of its base and stays there as an occluder that radiates nothing
//   (View3D removes it from the factors and the base's area);
// - an obstruction (O) only occludes, from both sides (its two faces, occluders only);
// - a mask (M) is refused: its factors are set by rule (1 to its base), not by the geometry.
// Coordinates are taken as metres; areas are reported in the file's units squared.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mesh/vs3_reader.h"
#include "solver/scene.h"
#include "solver/thermal/view_factors.h"

namespace lambert {

struct Vs3Scene {
  Scene scene;
  SurfaceGroups groups;           // the reported surfaces (combined), obstructions in none
  std::vector<double> emissivity;  // per scene surface (occluders: 1)
  std::vector<std::optional<double>> group_emissivity;  // per reported surface: its first part's
  vs3::Controls controls;
  std::string title;
  std::vector<std::string> warnings;  // the reader's ("NAME:LINE: message")
};

struct Vs3SceneResult {
  std::optional<Vs3Scene> scene;    // present iff errors is empty
  std::vector<std::string> errors;  // "NAME:LINE: message"
};

// The .vs3 text (`name` starts every message).
Vs3SceneResult vs3_scene(std::string_view text, std::string_view name);

}  // namespace lambert
