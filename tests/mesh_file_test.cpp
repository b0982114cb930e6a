// Tests of mesh/mesh_file.h: Lambert's own OBJ, PLY, OFF and STL readers. First that each format
// reads right (areas and volumes against closed forms), then one group per class of hostile input:
// files outside the mesh root (Sandbox), header counts (Counts), reads without an end (Bounds),
// double precision (Precision) and non-finite coordinates (NonFinite). Every input is written here.
#include "mesh/mesh_file.h"

#include <fcntl.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <limits>
#include <string>

#include "mesh/mesh_ops.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
const std::string kData = std::string(LAMBERT_SOURCE_DIR) + "/tests/data/";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

double total_area(const TriangleMesh& m) {
  double a = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) a += m.triangle(t).area();
  return a;
}

// Volume by the divergence theorem: positive when all faces face outwards.
double signed_volume(const TriangleMesh& m) {
  double v = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    v += dot(to_vector(m.triangle(t).centroid()), m.triangle(t).area_vector()) / 3;
  return v;
}

void expect_bounds(const TriangleMesh& m, const Point3& lo, const Point3& hi) {
  Bounds3 b;
  for (const Point3& p : m.vertices) b.add(p);
  EXPECT_EQ(b.lo, lo);
  EXPECT_EQ(b.hi, hi);
}

void expect_box(const MeshFileResult& r) {
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.mesh.vertices.size(), 8u);
  EXPECT_EQ(r.mesh.triangles.size(), 12u);           // 6 quads, 2 triangles each
  EXPECT_NEAR(total_area(r.mesh), 52.0, 1e-12);      // 2 (2*3 + 2*4 + 3*4)
  EXPECT_NEAR(signed_volume(r.mesh), 24.0, 1e-12);   // 2*3*4, outward orientation kept
  expect_bounds(r.mesh, {0, 0, 0}, {2, 3, 4});
  const MeshHealth h = check_mesh(r.mesh);
  EXPECT_EQ(h.boundary_edges, 0);
  EXPECT_TRUE(h.consistently_oriented);
}

void expect_tetra(const MeshFileResult& r) {
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.mesh.vertices.size(), 4u);
  EXPECT_EQ(r.mesh.triangles.size(), 4u);
  EXPECT_NEAR(total_area(r.mesh), 1.5 + std::sqrt(3.0) / 2, 1e-12);  // three right triangles + one equilateral of side sqrt 2
  EXPECT_NEAR(signed_volume(r.mesh), 1.0 / 6, 1e-15);
  expect_bounds(r.mesh, {0, 0, 0}, {1, 1, 1});
}

// A scratch directory per test, removed afterwards.
class MeshFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("lambert_mesh_file_test_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) {
    const fs::path p = dir_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
  }
  fs::path dir_;
};

template <typename T>
void append(std::string& out, T v) {
  char b[sizeof v];
  std::memcpy(b, &v, sizeof v);
  out.append(b, sizeof v);
}

// Binary STL: 80-byte header, facet count, then per facet a normal, three corners and 2 bytes.
std::string binary_stl(const std::vector<std::array<float, 9>>& facets, std::uint32_t declared) {
  std::string out(80, ' ');
  append(out, declared);
  for (const auto& f : facets) {
    for (int k = 0; k < 3; ++k) append(out, 0.0f);
    for (float c : f) append(out, c);
    append(out, std::uint16_t{0});
  }
  return out;
}

constexpr const char* kTetraObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

// ---- every format ---------------------------------------------------------------------------

using MeshFileFormats = MeshFileTest;

TEST_F(MeshFileFormats, ObjQuadsWithTextureCoordinates) { expect_box(read_mesh_file(kData + "box.obj")); }
TEST_F(MeshFileFormats, AsciiPly) { expect_box(read_mesh_file(kData + "box.ply")); }
TEST_F(MeshFileFormats, Off) { expect_tetra(read_mesh_file(kData + "tetra.off")); }
TEST_F(MeshFileFormats, AsciiStl) { expect_tetra(read_mesh_file(kData + "tetra.stl")); }
TEST_F(MeshFileFormats, ObjNegativeIndicesAndGroups) {
  expect_tetra(read_mesh_file(write("t.obj",
      "o tetra\nmtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl white\ng side\ns off\n"
      "f -4 -2 -3\nf 1/1 2/2 4/3\nf 1//1 4//1 3//1\nf 2/1/1 3/1/1 4/1/1\n")));
}

TEST_F(MeshFileFormats, OffWithCountsOnTheHeaderLineAndComments) {
  expect_tetra(read_mesh_file(write("t.off", "OFF 4 4 6 # counts\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n\n"
                                             "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3 # last face\n")));
}

TEST_F(MeshFileFormats, ColouredOffAndFaceColours) {
  expect_tetra(read_mesh_file(write("t.off", "COFF\n4 4 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 1 0 0 1 0\n0 0 1 0 0 1\n"
                                             "3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3 0.5 0.5 0.5 1\n")));
}

TEST_F(MeshFileFormats, BinaryStlWeldsCorners) {
  // The ascii tetrahedron written as binary STL; its 12 corners are 4 distinct points.
  const std::vector<std::array<float, 9>> facets = {{0, 0, 0, 0, 1, 0, 1, 0, 0},
                                                    {0, 0, 0, 1, 0, 0, 0, 0, 1},
                                                    {0, 0, 0, 0, 0, 1, 0, 1, 0},
                                                    {1, 0, 0, 0, 1, 0, 0, 0, 1}};
  expect_tetra(read_mesh_file(write("t.stl", binary_stl(facets, 4))));
}

// The box of box.ply as binary PLY, little- and big-endian, with a second list and an extra element.
std::string binary_box_ply(bool big_endian) {
  const float v[8][3] = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}, {0, 0, 4}, {2, 0, 4}, {2, 3, 4}, {0, 3, 4}};
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  std::string out = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nelement face 6\nproperty list uchar int vertex_indices\n"
                    "property list uchar float texcoord\nelement material 1\nproperty double shininess\nend_header\n";
  auto put = [&](auto value) {
    char b[sizeof value];
    std::memcpy(b, &value, sizeof value);
    if (big_endian) std::reverse(b, b + sizeof value);
    out.append(b, sizeof value);
  };
  for (const auto& p : v) {
    for (float c : p) put(c);
    put(std::uint8_t{200});
  }
  for (const auto& f : faces) {
    put(std::uint8_t{4});
    for (int i : f) put(std::int32_t{i});
    put(std::uint8_t{2});
    put(0.5f), put(0.25f);
  }
  put(10.0);
  return out;
}

TEST_F(MeshFileFormats, BinaryPlyBothByteOrders) {
  expect_box(read_mesh_file(write("le.ply", binary_box_ply(false))));
  expect_box(read_mesh_file(write("be.ply", binary_box_ply(true))));
}

TEST_F(MeshFileFormats, ConcaveFaceIsTriangulatedInsideIt) {
  const MeshFileResult r = read_mesh_file(kData + "l_shape.obj");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.mesh.triangles.size(), 4u);
  EXPECT_NEAR(total_area(r.mesh), 3.0, 1e-12);  // shoelace area of the L
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    EXPECT_GT(r.mesh.triangle(t).area_vector().z, 0) << "triangle " << t;
    const Point3 c = r.mesh.triangle(t).centroid();
    EXPECT_FALSE(c.x > 1 && c.y > 1) << "triangle " << t << " covers the notch";
  }
}

TEST_F(MeshFileFormats, NonManifoldFinIsKeptAsTheFileGivesIt) {
  // Three triangles on one edge: 5 vertices, 3 triangles, none detached or dropped.
  const MeshFileResult r = read_mesh_file(kData + "fin.obj");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.mesh.vertices.size(), 5u);
  EXPECT_EQ(r.mesh.triangles.size(), 3u);
  EXPECT_FALSE(check_mesh(r.mesh).manifold);
}

TEST_F(MeshFileFormats, MissingFileAndBadExtension) {
  const MeshFileResult r = read_mesh_file(kData + "no_such_file.obj");
  EXPECT_TRUE(contains(r.error, "does not exist")) << r.error;
  const MeshFileResult e = read_mesh_file(kData + "../mesh_file_test.cpp");
  EXPECT_TRUE(contains(e.error, "unsupported extension '.cpp'")) << e.error;
}

TEST_F(MeshFileFormats, ErrorsNameTheFileAndLine) {
  const std::string path = write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nbogus 1 2\n");
  EXPECT_EQ(read_mesh_file(path).error, path + ": line 5: unknown statement 'bogus'");
  const MeshFileResult degenerate = read_mesh_file(kData + "repeated_vertex.obj");
  EXPECT_TRUE(contains(degenerate.error, "repeated_vertex.obj: line 8: the face uses vertex 3 twice")) << degenerate.error;
  const MeshFileResult points = read_mesh_file(write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"));
  EXPECT_TRUE(contains(points.error, "the file has no faces")) << points.error;
  const MeshFileResult forward = read_mesh_file(write("fwd.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n"));
  EXPECT_TRUE(contains(forward.error, "line 2: vertex index 2 is out of range (1 vertices so far")) << forward.error;
  const std::string ply = parse_mesh("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n",
                                        MeshFormat::Ply).error;
  EXPECT_EQ(ply, "line 12: vertex 2: the line ends inside property 'z'");
}

// ---- Sandbox: the mesh file is the only file read -------------------------------------------

// Records every open and read of the files in a directory (inotify), so that a test sees whether
// the reader touched them, whatever they are.
class OpenWatch {
 public:
  explicit OpenWatch(const fs::path& path) {
    fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    watch_ = inotify_add_watch(fd_, path.c_str(), IN_OPEN | IN_ACCESS);
  }
  ~OpenWatch() { ::close(fd_); }
  bool valid() const { return fd_ >= 0 && watch_ >= 0; }
  int events() const {
    alignas(inotify_event) char buf[4096];
    int n = 0;
    for (ssize_t got; (got = ::read(fd_, buf, sizeof buf)) > 0;)
      for (char* p = buf; p < buf + got; p += sizeof(inotify_event) + reinterpret_cast<inotify_event*>(p)->len) ++n;
    return n;
  }

 private:
  int fd_ = -1, watch_ = -1;
};

using MeshFileSandbox = MeshFileTest;

TEST_F(MeshFileSandbox, MtllibOutsideTheRootIsNeverOpened) {
  // root/m.obj names ../outside/x.mtl, a FIFO: opening it for reading would block without a writer.
  const fs::path outside = dir_ / "outside";
  fs::create_directories(outside);
  ASSERT_EQ(::mkfifo((outside / "x.mtl").c_str(), 0600), 0);
  write("outside/y.mtl", "newmtl white\nKd 1 1 1\n");
  const std::string obj = write("root/m.obj", std::string("mtllib ../outside/x.mtl ../outside/y.mtl\nusemtl white\n") + kTetraObj);
  OpenWatch watch(outside);
  ASSERT_TRUE(watch.valid());
  auto read = std::async(std::launch::async, [&] { return read_mesh_file(obj); });
  const bool finished = read.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
  if (!finished) {  // unblock the reader before failing
    const int w = ::open((outside / "x.mtl").c_str(), O_WRONLY | O_NONBLOCK);
    if (w >= 0) ::close(w);
  }
  ASSERT_TRUE(finished) << "the reader blocked on the FIFO named by mtllib";
  expect_tetra(read.get());
  EXPECT_EQ(watch.events(), 0) << "the reader opened or read a file outside the mesh's own";
  std::ifstream((outside / "y.mtl").string()).get();  // the watch sees an open when there is one
  EXPECT_GT(watch.events(), 0);
}

TEST_F(MeshFileSandbox, MtllibDevZeroIsNotRead) {
  const std::string obj = write("root/a/b/m.obj", std::string("mtllib ../../../dev/zero\nmtllib /dev/zero\n") + kTetraObj);
  OpenWatch watch("/dev/zero");
  ASSERT_TRUE(watch.valid());
  expect_tetra(read_mesh_file(obj));
  EXPECT_EQ(watch.events(), 0) << "/dev/zero was opened";
  std::ifstream("/dev/zero").get();
  EXPECT_GT(watch.events(), 0);
}

TEST_F(MeshFileSandbox, FifoAsTheMeshFileIsRefusedWithoutBlocking) {
  const fs::path fifo = dir_ / "pipe.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto read = std::async(std::launch::async, [&] { return read_mesh_file(fifo.string()); });
  const bool finished = read.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
  if (!finished) {
    const int w = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (w >= 0) ::close(w);
  }
  ASSERT_TRUE(finished) << "opening a FIFO blocked";
  EXPECT_EQ(read.get().error, fifo.string() + ": not a regular file");
}

TEST_F(MeshFileSandbox, DevicesAndDirectoriesAreRefused) {
  const fs::path link = dir_ / "zero.obj";
  fs::create_symlink("/dev/zero", link);
  EXPECT_EQ(read_mesh_file(link.string()).error, link.string() + ": not a regular file");
  fs::create_directories(dir_ / "dir.obj");
  EXPECT_EQ(read_mesh_file((dir_ / "dir.obj").string()).error, (dir_ / "dir.obj").string() + ": not a regular file");
}

// ---- Counts: what a header declares is checked before it is allocated -----------------------

using MeshFileCounts = MeshFileTest;

const char* kPlyXyz = "property float x\nproperty float y\nproperty float z\n";

TEST_F(MeshFileCounts, PlyVertexCountBeyondTheLimit) {
  const std::string path = write("big.ply", std::string("ply\nformat ascii 1.0\nelement vertex 2000000000\n") + kPlyXyz +
                                                "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n");
  EXPECT_EQ(read_mesh_file(path).error,
            path + ": line 3: element vertex declares 2000000000 vertices; the limit is 10000000");
}

TEST_F(MeshFileCounts, PlyVertexCountBeyondTheFileSize) {
  // 5 million vertices (within the limit) declared by a file of a few hundred bytes.
  const std::string path = write("short.ply", std::string("ply\nformat binary_little_endian 1.0\nelement vertex 5000000\n") +
                                                  kPlyXyz + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                                                  std::string(40, '\0'));
  EXPECT_EQ(read_mesh_file(path).error, path + ": line 3: element vertex declares 5000000 vertices, but the 40 bytes "
                                               "that follow can hold at most 3");
}

TEST_F(MeshFileCounts, PlyFaceListCountOfInt32Max) {
  std::string ply = std::string("ply\nformat binary_little_endian 1.0\nelement vertex 3\n") + kPlyXyz +
                    "element face 1\nproperty list int int vertex_indices\nend_header\n";
  for (float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) append(ply, c);
  append(ply, std::int32_t{0x7FFFFFFF});
  append(ply, std::int32_t{0});
  const PolygonMeshResult r = parse_mesh(ply, MeshFormat::Ply);
  EXPECT_EQ(r.error, "face 0 (at byte 203): a face has 2147483647 vertices; at most 4096 are allowed");
  // The same in ascii, and a list that is not a face's, whose values the file does not hold.
  const PolygonMeshResult a = parse_mesh(std::string("ply\nformat ascii 1.0\nelement vertex 3\n") + kPlyXyz +
                                             "element face 1\nproperty list int int vertex_indices\nend_header\n"
                                             "0 0 0\n1 0 0\n0 1 0\n2147483647 0 1 2\n",
                                         MeshFormat::Ply);
  EXPECT_EQ(a.error, "line 13: face 0: a face has 2147483647 vertices; at most 4096 are allowed");
  std::string other = std::string("ply\nformat binary_little_endian 1.0\nelement vertex 1\n") + kPlyXyz +
                      "property list uint double weights\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (float c : {0.f, 0.f, 0.f}) append(other, c);
  append(other, std::uint32_t{0xFFFFFFFF});
  other += std::string(8, '\0');
  EXPECT_EQ(parse_mesh(other, MeshFormat::Ply).error,
            "vertex 0 (at byte 203): a list of 4294967295 values, but only 8 bytes are left");
}

TEST_F(MeshFileCounts, OffNegativeAndHugeCounts) {
  const std::string path = write("neg.off", "OFF\n-1 1 0\n");  // 11 bytes
  ASSERT_EQ(fs::file_size(path), 11u);
  EXPECT_EQ(read_mesh_file(path).error, path + ": line 2: the vertex count must be a whole number >= 0, got '-1'");
  EXPECT_EQ(parse_mesh("OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", MeshFormat::Off).error,
            "line 2: the header declares 2000000000 faces; the limit is 10000000");
  EXPECT_EQ(parse_mesh("OFF 9000000 1 0\n0 0 0\n", MeshFormat::Off).error,
            "line 1: the header declares 9000000 vertices, but the 6 bytes that follow can hold at most 1");
}

TEST_F(MeshFileCounts, StlFacetCountThatDoesNotMatchTheSize) {
  const std::string stl = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}}, 0x7FFFFFFF);
  EXPECT_EQ(parse_mesh(stl, MeshFormat::Stl).error,
            "not an STL file: it does not start with 'solid' (ascii) and its 134 bytes do not match a binary STL's "
            "size; as binary STL it declares 2147483647 facets, which take 107374182434 bytes");
}

TEST_F(MeshFileCounts, LimitsAreTheCallersToSet) {
  MeshReadLimits limits;
  limits.max_vertices = 3;
  EXPECT_EQ(parse_mesh(kTetraObj, MeshFormat::Obj, limits).error, "line 4: more than 3 vertices (the limit)");
  limits = {};
  limits.max_faces = 2;
  EXPECT_EQ(parse_mesh(kTetraObj, MeshFormat::Obj, limits).error, "line 7: more than 2 faces (the limit)");
}

// ---- Bounds: every read ends, within the file -----------------------------------------------

using MeshFileBounds = MeshFileTest;

TEST_F(MeshFileBounds, PlyWithoutEndHeader) {
  // A megabyte of header lines: the reader gives up after 64 KiB.
  std::string ply = "ply\nformat ascii 1.0\n";
  while (ply.size() < (1u << 20)) ply += "comment no end in sight\n";
  const std::string path = write("endless.ply", ply);
  EXPECT_EQ(read_mesh_file(path).error, path + ": no 'end_header' line in the first 65536 bytes");
  EXPECT_EQ(parse_mesh("ply\nformat ascii 1.0\nelement vertex 3\n", MeshFormat::Ply).error,
            "the header has no 'end_header' line");
  EXPECT_EQ(parse_mesh("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x", MeshFormat::Ply).error,
            "the header has no 'end_header' line");
}

TEST_F(MeshFileBounds, ObjFaceWithAHundredThousandVertices) {
  std::string obj;
  for (int k = 0; k < 100000; ++k) {
    const double a = 2 * 3.141592653589793 * k / 100000;
    obj += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0\n";
  }
  obj += "f";
  for (int k = 1; k <= 100000; ++k) obj.append(" ").append(std::to_string(k));
  obj += "\n";
  const std::string path = write("round.obj", obj);
  EXPECT_EQ(read_mesh_file(path).error, path + ": line 100001: a face has more than 4096 vertices (the limit)");
}

TEST_F(MeshFileBounds, TheLargestAllowedConcaveFaceIsTriangulated) {
  // A 4096-gon star (alternating radii 1 and 0.5): concave, so it takes the constrained triangulation.
  const int n = 4096;
  std::string obj;
  double area = 0;  // shoelace
  std::vector<std::pair<double, double>> p;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * 3.141592653589793 * k / n, r = k % 2 ? 0.5 : 1.0;
    p.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  for (int k = 0; k < n; ++k) {
    char line[96];
    std::snprintf(line, sizeof line, "v %.17g %.17g 0\n", p[k].first, p[k].second);
    obj += line;
    area += 0.5 * (p[k].first * p[(k + 1) % n].second - p[(k + 1) % n].first * p[k].second);
  }
  obj += "f";
  for (int k = 1; k <= n; ++k) obj.append(" ").append(std::to_string(k));
  const MeshFileResult r = read_mesh_file(write("star.obj", obj + "\n"));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.mesh.triangles.size(), std::size_t(n - 2));
  EXPECT_NEAR(total_area(r.mesh), area, 1e-9 * area);
}

TEST_F(MeshFileBounds, FileLargerThanTheLimit) {
  MeshReadLimits limits;
  limits.max_file_bytes = 100;
  const std::string path = write("t.obj", std::string(kTetraObj) + std::string(100, '#') + "\n");
  EXPECT_EQ(read_mesh_file(path, limits).error, path + ": the file has 165 bytes; the limit is 100");
}

TEST_F(MeshFileBounds, TruncatedFilesEndWithAnError) {
  std::string ply = binary_box_ply(false);
  ply.resize(ply.size() - 30);
  EXPECT_EQ(parse_mesh(ply, MeshFormat::Ply).error, "face 5 (at byte 502): a list of 4 values, but only 3 bytes are left");
  EXPECT_EQ(parse_mesh("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n# padding, not a face\n", MeshFormat::Off).error,
            "the file ends after 1 of its 2 faces");
  EXPECT_EQ(parse_mesh("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", MeshFormat::Stl).error,
            "the file ends inside a solid (no 'endsolid' after line 4)");
  EXPECT_EQ(parse_mesh("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", MeshFormat::Off).error,
            "line 7: data after the last face");
}

// ---- Precision: coordinates are doubles ------------------------------------------------------

using MeshFilePrecision = MeshFileTest;

// x = 500000.3 is 500000.3125 as a float: a 12 mm error on geo-referenced files.
constexpr double kGeo = 500000.3;

void expect_geo_vertex(const PolygonMeshResult& r, const char* format) {
  ASSERT_TRUE(r.ok()) << format << ": " << r.error;
  EXPECT_EQ(r.mesh.vertices[0].x, kGeo) << format;
  EXPECT_EQ(r.mesh.vertices[0].y, 4000000.7) << format;
  EXPECT_EQ(r.mesh.vertices[1].z, 0.1) << format;
}

TEST_F(MeshFilePrecision, TextFormatsKeepEveryDigit) {
  expect_geo_vertex(parse_mesh("v 500000.3 4000000.7 0\nv 500001.3 4000000.7 0.1\nv 500000.3 4000001.7 0\nf 1 2 3\n",
                               MeshFormat::Obj), "obj");
  expect_geo_vertex(parse_mesh("OFF\n3 1 0\n500000.3 4000000.7 0\n500001.3 4000000.7 0.1\n500000.3 4000001.7 0\n3 0 1 2\n",
                               MeshFormat::Off), "off");
  expect_geo_vertex(parse_mesh(std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                                           "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                           "end_header\n500000.3 4000000.7 0\n500001.3 4000000.7 0.1\n500000.3 4000001.7 0\n3 0 1 2\n"),
                               MeshFormat::Ply), "ply ascii");
  expect_geo_vertex(parse_mesh("solid g\nfacet normal 0 0 1\nouter loop\nvertex 500000.3 4000000.7 0\n"
                               "vertex 500001.3 4000000.7 0.1\nvertex 500000.3 4000001.7 0\nendloop\nendfacet\nendsolid g\n",
                               MeshFormat::Stl), "stl ascii");
}

TEST_F(MeshFilePrecision, BinaryPlyDoubles) {
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                    "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  for (double c : {kGeo, 4000000.7, 0.0, 500001.3, 4000000.7, 0.1, kGeo, 4000001.7, 0.0}) append(ply, c);
  append(ply, std::uint8_t{3});
  for (std::uint32_t i : {0u, 1u, 2u}) append(ply, i);
  expect_geo_vertex(parse_mesh(ply, MeshFormat::Ply), "ply binary");
}

TEST_F(MeshFilePrecision, ThroughTheFileReaderToo) {
  const MeshFileResult r = read_mesh_file(write("geo.obj", "v 500000.3 0 0\nv 500001.3 0 0\nv 500000.3 1 0\nf 1 2 3\n"));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.mesh.vertices[0].x, kGeo);
  EXPECT_NE(static_cast<double>(static_cast<float>(kGeo)), kGeo);  // what a float reader would have returned
}

// ---- NonFinite: NaN and infinity are refused, naming the element -----------------------------

using MeshFileNonFinite = MeshFileTest;

TEST_F(MeshFileNonFinite, TextFormats) {
  const std::string stl = write("nan.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                           "vertex 0 nan 0\nendloop\nendfacet\nendsolid t\n");
  EXPECT_EQ(read_mesh_file(stl).error, stl + ": line 8: facet 0: corner 3: a coordinate is not finite (y = nan)");
  EXPECT_EQ(parse_mesh("v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj).error,
            "line 2: vertex 2 has a coordinate that is not finite (z = inf)");
  EXPECT_EQ(parse_mesh("v 0 0 0\nv -1.#IND 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj).error,
            "line 2: vertex 2 has a coordinate that is not finite (x = -1.#IND)");
  EXPECT_EQ(parse_mesh("OFF\n3 1 0\n0 0 0\n1 0 0\n0 -inf 0\n3 0 1 2\n", MeshFormat::Off).error,
            "line 5: vertex 2: a coordinate is not finite (y = -inf)");
  EXPECT_EQ(parse_mesh(std::string("ply\nformat ascii 1.0\nelement vertex 3\n") + kPlyXyz +
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\nNaN 0 0\n0 1 0\n3 0 1 2\n",
                       MeshFormat::Ply).error,
            "line 11: vertex 1: a coordinate is not finite (x = nan)");
  EXPECT_EQ(parse_mesh("v 0 0 0\nv 1e400 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj).error,
            "line 2: vertex 2: '1e400' is out of the double range");
}

TEST_F(MeshFileNonFinite, BinaryFormats) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(parse_mesh(binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 1, 0, 0, 0, 0, inf}}, 2), MeshFormat::Stl).error,
            "facet 1 (at byte 134): corner 3: a coordinate is not finite (z = inf)");
  std::string ply = std::string("ply\nformat binary_little_endian 1.0\nelement vertex 3\n") + kPlyXyz +
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (float c : {0.f, 0.f, 0.f, 1.f, nan, 0.f, 0.f, 1.f, 0.f}) append(ply, c);
  append(ply, std::uint8_t{3});
  for (std::int32_t i : {0, 1, 2}) append(ply, i);
  EXPECT_EQ(parse_mesh(ply, MeshFormat::Ply).error, "vertex 1 (at byte 181): a coordinate is not finite (y = nan)");
}

}  // namespace
}  // namespace lambert
