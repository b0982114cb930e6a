// The pieces of the .vs3 reader (mesh/vs3_reader.h) that its two files share: the message collector
// and the checks of the surfaces once every line is read (vs3_checks.cpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mesh/vs3_reader.h"

namespace lambert::vs3 {

// "NAME:LINE: message" collection, at most kMaxErrors errors (then a count).
class Messages {
 public:
  explicit Messages(std::string_view name) : name_(name) {}
  void error(int line, const std::string& message);
  void warn(int line, const std::string& message, std::vector<std::string>& into) const;
  bool any() const { return !errors_.empty() || dropped_ > 0; }
  std::vector<std::string> take();

 private:
  std::string where(int line) const;
  std::string name_;
  std::vector<std::string> errors_;
  std::size_t dropped_ = 0;
};

// Every surface's polygon (distinct corners, an area, a plane and convexity for quads) and its
// references (base, combination) as View3D requires them, and each subsurface, mask and null surface
// in its base's plane, facing as its kind requires, and inside its base (View3D's TestSubSrf).
void check_surfaces(const Input& input, Messages& messages);

}  // namespace lambert::vs3
