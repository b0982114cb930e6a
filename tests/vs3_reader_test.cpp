// Tests of mesh/vs3_reader.h, View3D's input files: what the files in tests/data/view3d/ hold, the
// same room read from both geometries (F 3 and F 3a), and one error per rule, each naming its line.
#include "mesh/vs3_reader.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace lambert::vs3 {
namespace {

const std::string kData = std::string(LAMBERT_SOURCE_DIR) + "/tests/data/view3d/";

std::string file_text(const std::string& name) {
  std::ifstream in(kData + name, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Input read_ok(const std::string& text, const std::string& name = "t.vs3") {
  ReadResult r = read_vs3(text, name);
  std::string errors;
  for (const std::string& e : r.errors) errors += e + "\n";
  EXPECT_TRUE(r.ok()) << errors;
  return r.ok() ? std::move(*r.input) : Input{};
}

// The errors of `text`, which must fail; each must start with "t.vs3:".
std::string read_errors(const std::string& text) {
  ReadResult r = read_vs3(text, "t.vs3");
  EXPECT_FALSE(r.ok()) << text;
  std::string all;
  for (const std::string& e : r.errors) {
    EXPECT_EQ(e.rfind("t.vs3:", 0), 0u) << e;
    all += e + "\n";
  }
  return all;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A file with the unit square floor and ceiling: `more` lines are added after them.
std::string two_squares(const std::string& more = "") {
  return "T two squares\nF 3\n"
         "V 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\nV 5 0 0 1\nV 6 1 0 1\nV 7 1 1 1\nV 8 0 1 1\n"
         "S 1 1 2 3 4 0 0 0.9 floor\nS 2 5 8 7 6 0 0 0.9 ceiling\n" +
         more;
}

TEST(Vs3Reader, TheCube) {
  const Input in = read_ok(file_text("cube.vs3"), "cube.vs3");
  EXPECT_EQ(in.title, "Unit cube, every face facing in (View3D's manual example)");
  EXPECT_TRUE(in.controls.enclosure);
  EXPECT_FALSE(in.controls.emittances);
  EXPECT_EQ(in.geometry, Geometry::Vertices);
  ASSERT_EQ(in.vertices.size(), 8u);
  ASSERT_EQ(in.surfaces.size(), 6u);
  const char* names[] = {"floor", "ceiling", "west", "east", "south", "north"};
  for (int i = 0; i < 6; ++i) {
    const Surface& s = in.surfaces[i];
    EXPECT_EQ(s.number, i + 1);
    EXPECT_EQ(s.name, names[i]);
    EXPECT_EQ(s.kind, SurfaceKind::Radiating);
    EXPECT_EQ(s.polygon.size(), 4u);
    EXPECT_DOUBLE_EQ(*s.emissivity, 0.9);
    // Every face faces the cube's centre (0.5, 0.5, 0.5): the polygon is counter-clockwise from there.
    const Vector3 n = cross(s.polygon[1] - s.polygon[0], s.polygon[2] - s.polygon[1]);
    EXPECT_GT(dot(n, Point3{0.5, 0.5, 0.5} - s.polygon[0]), 0) << s.name;
  }
  EXPECT_EQ(in.surfaces[1].polygon[1], (Point3{0, 1, 1}));  // vertex 8
}

TEST(Vs3Reader, ObstructionOnlyAndRadiatingMiddleSquare) {
  const Input a = read_ok(file_text("squares_obstructed.vs3"));
  const Input b = read_ok(file_text("squares_obstruction_only.vs3"));
  ASSERT_EQ(a.surfaces.size(), 3u);
  ASSERT_EQ(b.surfaces.size(), 3u);
  EXPECT_EQ(a.surfaces[2].kind, SurfaceKind::Radiating);
  EXPECT_EQ(a.surfaces[2].name, "middle");
  EXPECT_EQ(b.surfaces[2].kind, SurfaceKind::Obstruction);
  EXPECT_EQ(b.surfaces[2].name, "obstruction-3");
  EXPECT_FALSE(b.surfaces[2].emissivity);
  EXPECT_EQ(a.surfaces[2].polygon, b.surfaces[2].polygon);
  EXPECT_EQ(b.surfaces[2].polygon[2], (Point3{0.5, 0.5, 0.5}));
}

TEST(Vs3Reader, TheSameRoomInBothGeometries) {
  // l_room_3a.vs3 places rectangles by origin, azimuth and tilt (View3D's GetVS3Da); l_room_3.vs3
  // lists the same corners as vertices. The polygons agree corner for corner (the same cyclic order,
  // the same first corner), exactly: the angles are multiples of 90°.
  const Input blast = read_ok(file_text("l_room_3a.vs3"));
  const Input vertices = read_ok(file_text("l_room_3.vs3"));
  EXPECT_EQ(blast.geometry, Geometry::Blast);
  EXPECT_TRUE(blast.vertices.empty());
  ASSERT_EQ(blast.surfaces.size(), 10u);
  ASSERT_EQ(vertices.surfaces.size(), 10u);
  for (std::size_t i = 0; i < 10; ++i) {
    const Surface &s = blast.surfaces[i], &t = vertices.surfaces[i];
    EXPECT_EQ(s.name, t.name);
    EXPECT_EQ(s.combine, t.combine);
    EXPECT_EQ(*s.emissivity, *t.emissivity);
    EXPECT_EQ(s.polygon, t.polygon) << s.name;
  }
  EXPECT_EQ(blast.surfaces[7].combine, 7);
  EXPECT_EQ(blast.surfaces[9].line, 26);  // the Q surface, its numbers on the two lines after it
}

TEST(Vs3Reader, SubsurfacesMasksNullSurfacesAndSeparators) {
  // A window (subsurface) in the floor, a mask and a null surface in the window and the floor, words
  // separated by commas and tabs, Windows line ends, comments at line ends and on their own lines.
  const std::string text =
      two_squares() +
      "V 9 0.2 0.2 0\r\nV 10 0.4 0.2 0\r\nV 11 0.4 0.4 0\r\nV 12 0.2 0.4 0\r\n"
      "V,13,0.6,0.6,0\nV\t14\t0.8\t0.6\t0\nV 15 0.8 0.8 0 ! a comment\nV 16 0.6 0.8 0 / another\n"
      "/ a comment line\n"
      "S 3 9 10 11 12 1 0 0.5 window\n"
      "M 4 13 16 15 14 1 0 0.5 rug\n"
      "N 5 9 12 11 10 3 0 0.5 hole\n"
      "E\nanything at all after the end of data\n";
  const Input in = read_ok(text);
  ASSERT_EQ(in.surfaces.size(), 5u);
  EXPECT_EQ(in.surfaces[2].base, 1);
  EXPECT_EQ(in.surfaces[3].kind, SurfaceKind::Mask);
  EXPECT_EQ(in.surfaces[4].kind, SurfaceKind::Null);
  EXPECT_EQ(in.surfaces[4].base, 3);
  EXPECT_EQ(in.surfaces[3].polygon[2], (Point3{0.8, 0.8, 0}));
}

TEST(Vs3Reader, ControlsAsViewThreeDSplitsThem) {
  const Input in = read_ok(two_squares() + "C eps = 1e-5, maxU=8 maxO 10 minO=1 encl=1 emit=1 out=0 list=2\n");
  EXPECT_EQ(in.controls.eps, 1e-5);
  EXPECT_EQ(in.controls.max_u, 8);
  EXPECT_EQ(in.controls.max_o, 10);
  EXPECT_EQ(in.controls.min_o, 1);
  EXPECT_TRUE(in.controls.enclosure);
  EXPECT_TRUE(in.controls.emittances);
  EXPECT_EQ(in.controls.list, 2);
  const Input rows = read_ok(two_squares() + "C row=2 col=1\n");
  EXPECT_EQ(rows.controls.row, 2);
  ASSERT_EQ(rows.warnings.size(), 1u);
  EXPECT_TRUE(contains(rows.warnings[0], "t.vs3:13: row/col"));
}

TEST(Vs3Reader, ErrorsNameTheLine) {
  EXPECT_TRUE(contains(read_errors(two_squares("Q 3\n")), "t.vs3:13: unknown line type 'Q'"));
  EXPECT_TRUE(contains(read_errors(two_squares("Surface 3\n")), "t.vs3:13: unknown line type 'Surface'"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 10 0 0 0\n")), "t.vs3:13: vertex '10' out of sequence: expected 9"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 nan 0 0\n")), "t.vs3:13: vertex 9: x is not a finite number: 'nan'"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 0 inf 0\n")), "y is not a finite number: 'inf'"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 0 0 1e999\n")), "z is not a finite number"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 0 0 2e9\n")), "|z| exceeds 1e9"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 0 0\n")), "t.vs3:13: expected 'V n x y z'"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 4 1 2 3 4 0 0 0.9 x\n")), "t.vs3:13: surface '4' out of sequence: expected 3"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 0 1.5 x\n")),
                       "t.vs3:13: surface 3: the emissivity must be a number in [0, 1], got '1.5'"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 0 NaN x\n")), "emissivity must be a number"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 0 0.9\n")), "t.vs3:13: expected 'S n v1 v2 v3 v4 base cmb emit name'"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 0 0.9 x extra\n")), "got 11 words"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 9 0 0 0.9 x\n")), "vertex 4 is 9, not defined before this line"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 -1 0 0 0.9 x\n")), "surface 3: vertex 4 -1 is outside [0,"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 1 3 0 0 0 0.9 x\n")), "t.vs3:13: surface 3 (x): corners 1 and 2 coincide"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 2 0 0\nS 3 1 2 9 0 0 0 0.9 x\n")), "t.vs3:14: surface 3 (x) has no area"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 0.2 0.2 0\nS 3 1 2 9 4 0 0 0.9 x\n")), "is not a convex quadrilateral"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 1 1 0.01\nS 3 1 2 9 4 0 0 0.9 x\n")), "are not in one plane"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 0 0.9 bad\x01name\n")), "the name must be UTF-8 text"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 0 0.9 bad\xc0\xafname\n")), "the name must be UTF-8 text"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 0 0.9 " + std::string(101, 'n') + "\n")),
                       "at most 100 bytes"));
  EXPECT_TRUE(contains(read_errors(two_squares("C encl=2\n")), "t.vs3:13: control encl 2 is outside [0, 1]"));
  EXPECT_TRUE(contains(read_errors(two_squares("C epsilon=1\n")), "t.vs3:13: unknown control 'epsilon'"));
  EXPECT_TRUE(contains(read_errors(two_squares("C encl\n")), "control 'encl' has no value"));
  EXPECT_TRUE(contains(read_errors(two_squares("C col=1\n")), "control col needs row"));
  EXPECT_TRUE(contains(read_errors(two_squares("C row=3\n")), "exceeds the 2 radiating surfaces"));
  EXPECT_TRUE(contains(read_errors(two_squares("F 3a\n")), "t.vs3:13: a second F line with another geometry (the first is on line 2)"));
  EXPECT_TRUE(contains(read_errors("F 2\n"), "t.vs3:1: geometry '2' is not read here: F 2 is View3D's 2-D geometry"));
  EXPECT_TRUE(contains(read_errors("T nothing\nV 1 0 0 0\n"), "t.vs3:2: a vertex before the F 3 line"));
  EXPECT_TRUE(contains(read_errors("T nothing\n"), "t.vs3:0: no F line"));
  EXPECT_TRUE(contains(read_errors(two_squares(std::string("V 9 0 0 0\0\n", 12))), "t.vs3:13: the line holds a NUL byte"));
  EXPECT_TRUE(contains(read_errors(two_squares(std::string(5000, ' ') + "\n")), "t.vs3:13: the line has 5000 bytes"));
}

TEST(Vs3Reader, ErrorsOfReferencesAndSubsurfaces) {
  const std::string inner = "V 9 0.2 0.2 0\nV 10 0.4 0.2 0\nV 11 0.4 0.4 0\nV 12 0.2 0.4 0\n";
  // lines 13-16 are the inner vertices, 17 the surface
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "S 3 9 10 11 12 5 0 0.9 w\n")),
                       "t.vs3:17: surface 3 (w): base 5 is not another surface of the file"));
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "S 3 9 12 11 10 1 0 0.9 w\n")),
                       "t.vs3:17: surface 3 (w) must face the way its base 1 faces"));
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "S 3 9 10 11 12 2 0 0.9 w\n")),
                       "surface 3 (w) does not lie in the plane of its base 2"));
  EXPECT_TRUE(contains(read_errors(two_squares("V 9 0.5 0.5 0\nV 10 1.5 0.5 0\nV 11 1.5 1.5 0\nS 3 9 10 11 0 1 0 0.9 w\n")),
                       "surface 3 (w) is not inside its base 1"));
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "M 3 9 10 11 12 1 0 0.9 m\n")), "must face its base 1 (the opposite way)"));
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "N 3 9 12 11 10 0 0 0.9 m\n")),
                       "a mask or null surface needs a base"));
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "S 3 9 10 11 12 0 3 0.9 w\n")), "combination 3 must be an earlier surface"));
  EXPECT_TRUE(contains(read_errors(two_squares("S 3 1 2 3 4 0 2 0.9 a\nS 4 1 2 3 4 0 3 0.9 b\n")),
                       "t.vs3:14: surface 4 (b): combination 3 is itself combined with another"));
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "O 3 9 10 11 12\nS 4 9 10 11 12 1 0 0.9 w\n")),
                       "surface 4 (S) follows an obstruction"));
  EXPECT_TRUE(contains(read_errors(two_squares(inner + "O 3 9 10 11 12 1 0 0.9 o\n")),
                       "obstruction 3 can have neither a base nor a combination"));
  // An obstruction may be a subsurface's base although it comes later (View3D numbers obstructions last).
  read_ok(two_squares(inner + "S 3 9 10 11 12 4 0 0.9 window\nO 4 9 10 11 12 0 0 0 pane\n"));
}

TEST(Vs3Reader, BlastShapesAndTheirErrors) {
  // A 2 × 1 rectangle facing east (azimuth 90): its corners (0, h), (0, 0), (w, 0), (w, h) map to
  // x = x0, y = y0 + u, z = z0 + v (View3D's GetVS3Da at a = 90°, t = 90°).
  const Input in = read_ok("F 3a\nS 1 R 0 0 0.9 east\n 5 1 0  90 90  2 1\nS 2 T 0 0 0.9 t\n0 0 0 180 0\n0 0 1 0 0 1\n");
  ASSERT_EQ(in.surfaces.size(), 2u);
  const std::vector<Point3> east = {{5, 1, 1}, {5, 1, 0}, {5, 3, 0}, {5, 3, 1}};
  EXPECT_EQ(in.surfaces[0].polygon, east);
  EXPECT_EQ(in.surfaces[1].polygon, (std::vector<Point3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));  // facing up
  EXPECT_TRUE(contains(read_errors("F 3a\nS 1 P 0 0 0.9 x\n1 2 3 4 5 6 7\n"),
                       "t.vs3:2: surface 1: shape 'P' is not R (rectangle), Q (quadrilateral) or T (triangle)"));
  EXPECT_TRUE(contains(read_errors("F 3a\nS 1 R 0 0 0.9 x\n1 2 3 4 5 6\nS 2 R 0 0 0.9 y\n1 2 3 4 5 6 7\n"),
                       "t.vs3:2: surface 1 needs 7 numbers on the lines after it"));
  EXPECT_TRUE(contains(read_errors("F 3a\nS 1 R 0 0 0.9 x\n1 2 3 4 5 6 7 8\n"), "t.vs3:3: surface 1: more than the 7 numbers"));
  EXPECT_TRUE(contains(read_errors("F 3a\nS 1 R 0 0 0.9 x\n1 2 3 4 5 0 7\n"), "width and height must be > 0"));
  EXPECT_TRUE(contains(read_errors("F 3a\nS 1 R 0 0 0.9 x\n1 2 3 4 5 6 x7\n"), "t.vs3:3: surface 1: expected a number, got 'x7'"));
  EXPECT_TRUE(contains(read_errors("F 3a\nS 1 R 0 0 0.9 x\n"), "t.vs3:2: surface 1 needs 7 numbers"));
  EXPECT_TRUE(contains(read_errors("F 3a\nV 1 0 0 0\n"), "vertices (V) belong to F 3 files"));
}

TEST(Vs3Reader, ErrorsAreCapped) {
  std::string text = "F 3\n";
  for (int k = 0; k < 500; ++k) text += "Q\n";
  const ReadResult r = read_vs3(text, "t.vs3");
  ASSERT_EQ(r.errors.size(), kMaxErrors + 1);
  EXPECT_EQ(r.errors.back(), "t.vs3: 400 more errors not shown");
}

}  // namespace
}  // namespace lambert::vs3
