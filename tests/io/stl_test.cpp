// STL reading: both encodings, welding, and errors that say where and what was expected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

#include "cwe/core/error.hpp"
#include "cwe/io/mesh_io.hpp"

namespace cwe {
namespace {

// A tetrahedron with outward faces.
TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return m;
}

const char* const kAsciiTetrahedron =
    "solid tet exported by hand\n"
    "facet normal 0 0 -1\n outer loop\n  vertex 0 0 0\n  vertex 0 1 0\n  vertex 1 0 0\n"
    " endloop\nendfacet\n"
    "FACET NORMAL 0 -1 0\n OUTER LOOP\n  VERTEX 0 0 0\n  VERTEX +1 0 0\n  VERTEX 0 0 1\n"
    " ENDLOOP\nENDFACET\n"
    "endsolid tet\n"
    "solid second\n"
    "facet normal 1 1 1\n outer loop\n  vertex 1e0 0 0\n  vertex 0 1 0\n  vertex 0 0 1.0\n"
    " endloop\nendfacet\n"
    "facet normal -1 0 0\n outer loop\n  vertex -0 0 0\n  vertex 0 0 1\n  vertex 0 1 0\n"
    " endloop\nendfacet\n"
    "endsolid second\n";

std::string error_of(const std::string& bytes) {
  try {
    parse_stl(bytes, "part.stl");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Stl, AsciiIsReadAndWelded) {
  const StlMesh read = parse_stl(kAsciiTetrahedron, "tet.stl");
  EXPECT_FALSE(read.binary);
  EXPECT_EQ(read.mesh.vertices.size(), 4u);  // -0 welds with 0, 1e0 with 1
  EXPECT_EQ(read.mesh.triangles.size(), 4u);
  EXPECT_TRUE(check_closure(read.mesh).closed());
  EXPECT_NEAR(read.mesh.volume(), 1.0 / 6.0, 1e-15);
}

TEST(Stl, BinaryRoundTripsEvenWithASolidHeader) {
  for (const char* header : {"cwe test", "solid looks like ASCII"}) {
    const std::string bytes = stl_binary(tetrahedron(), header);
    const StlMesh read = parse_stl(bytes, "tet.stl");
    EXPECT_TRUE(read.binary) << header;
    // Vertices are numbered in order of first appearance; the corners, in order, are the same.
    ASSERT_EQ(read.mesh.triangles.size(), 4u);
    EXPECT_EQ(read.mesh.vertices.size(), 4u);
    for (std::size_t t = 0; t < 4; ++t) {
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(read.mesh.vertices[static_cast<std::size_t>(read.mesh.triangles[t][k])],
                  tetrahedron().vertices[static_cast<std::size_t>(tetrahedron().triangles[t][k])]);
      }
    }
  }
}

// Written while the mesh is made (stock.stl while the stock is contoured): a header with no
// count, the facets in runs of any length, then the header again with the count, give the bytes
// of the whole mesh written at once.
TEST(Stl, BinaryInRunsIsTheWholeMeshsBytes) {
  TriangleMesh m;
  for (int k = 0; k < 3000; ++k) m.vertices.emplace_back(0.1 * k, std::sin(k), 1.0 / (k + 1));
  for (int k = 0; k < 9001; ++k) m.triangles.push_back({k % 3000, (7 * k + 1) % 3000, k / 3});
  const std::string whole = stl_binary(m, "runs");
  std::string bytes = stl_binary_header("runs", 0);
  const auto write = [&bytes](std::string_view piece) { bytes.append(piece); };
  std::size_t at = 0;
  for (const std::size_t run : {1, 3999, 4001, 0, 1000}) {
    stl_binary_facets(std::span(m.triangles).subspan(at, run), m.vertices, write);
    at += run;
  }
  stl_binary_facets(std::span(m.triangles).subspan(at), m.vertices, write);
  ASSERT_EQ(bytes.size(), whole.size());
  EXPECT_NE(bytes, whole);  // the count
  bytes.replace(0, 84, stl_binary_header("runs", m.triangles.size()));
  EXPECT_EQ(bytes, whole);
}

TEST(Stl, DegenerateFacetsAreDroppedAndCounted) {
  TriangleMesh m = tetrahedron();
  m.triangles.push_back({1, 1, 2});
  const StlMesh read = parse_stl(stl_binary(m, "x"), "x.stl");
  EXPECT_EQ(read.degenerate_dropped, 1);
  EXPECT_EQ(read.mesh.triangles.size(), 4u);
}

TEST(Stl, ErrorsNameTheFileThePlaceAndWhatWasExpected) {
  const std::string binary = stl_binary(tetrahedron(), "x");
  std::string what = error_of(binary.substr(0, binary.size() - 1));
  EXPECT_NE(what.find("part.stl"), std::string::npos) << what;
  EXPECT_NE(what.find("truncated"), std::string::npos) << what;
  EXPECT_NE(what.find("triangle 4"), std::string::npos) << what;
  what = error_of(binary + "extra");
  EXPECT_NE(what.find("5 bytes after"), std::string::npos) << what;
  std::string nan = binary;
  const std::uint32_t nan_bits = 0x7FC00000u;
  std::memcpy(nan.data() + 84 + 50 + 12 + 4, &nan_bits, 4);  // triangle 2, first corner's y
  what = error_of(nan);
  EXPECT_NE(what.find("triangle 2"), std::string::npos) << what;
  EXPECT_NE(what.find("NaN"), std::string::npos) << what;

  std::string ascii = kAsciiTetrahedron;
  ascii.replace(ascii.find("vertex 0 1 0"), 12, "vertex 0 one 0");
  what = error_of(ascii);
  EXPECT_NE(what.find("part.stl:5:12"), std::string::npos) << what;
  EXPECT_NE(what.find("expected a number"), std::string::npos) << what;
  ascii = kAsciiTetrahedron;
  ascii.replace(ascii.find("  vertex 1 0 0\n"), 15, "");
  what = error_of(ascii);
  EXPECT_NE(what.find("facet with 2 vertices: expected 3"), std::string::npos) << what;
  ascii = kAsciiTetrahedron;
  ascii.replace(ascii.find("vertex 0 0 1.0"), 14, "vertex 0 0 1e40");
  what = error_of(ascii);
  EXPECT_NE(what.find("out of range"), std::string::npos) << what;
  ascii = kAsciiTetrahedron;
  ascii.replace(ascii.find("endfacet\nFACET"), 8, "endfacit");
  what = error_of(ascii);
  EXPECT_NE(what.find("expected 'endfacet'"), std::string::npos) << what;
  what = error_of("solid empty\nendsolid empty\n");
  EXPECT_NE(what.find("no triangles"), std::string::npos) << what;
  what = error_of("");
  EXPECT_NE(what.find("empty file"), std::string::npos) << what;
  EXPECT_THROW(read_stl("/nonexistent/part.stl"), InputError);
}

}  // namespace
}  // namespace cwe
