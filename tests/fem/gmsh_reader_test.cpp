// Gmsh MSH 4.1 import: the two hand-written meshes of tests/fem/data, and malformed variants of the
// rectangle written to temporary files, each of which must fail with the file, the line and the problem.
#include "fem/gmsh_reader.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace csim {
namespace {

#ifdef CSIM_SOURCE_DIR
const std::string kDataDirectory = std::string(CSIM_SOURCE_DIR) + "/tests/fem/data/";
#else
const std::string kDataDirectory = std::filesystem::path(__FILE__).parent_path().string() + "/data/";
#endif
const std::string kRectangle = kDataDirectory + "rectangle_2x1.msh";
const std::string kCube = kDataDirectory + "unit_cube_hexa.msh";

std::string file_text(const std::string& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// The 1-based line of the first occurrence of `needle` in `text`.
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

// Writes `text` to a temporary file named after the test, reads it, returns the error message.
class MalformedGmshTest : public ::testing::Test {
 protected:
  void TearDown() override {
    if (!path_.empty()) std::filesystem::remove(path_);
  }

  std::string error_reading(const std::string& text) {
    write(text);
    try {
      read_gmsh(path_);
    } catch (const FemError& error) {
      return error.what();
    }
    return "no FemError";
  }

  // Writes `text` to the test's temporary file.
  void write(const std::string& text) {
    path_ = (std::filesystem::temp_directory_path() /
             ("csim_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
              std::to_string(::getpid()) + ".msh"))
                .string();
    std::ofstream(path_, std::ios::binary) << text;
  }

  // Replaces the first occurrence of `from` in the rectangle file.
  static std::string rectangle_with(const std::string& from, const std::string& to) {
    std::string text = file_text(kRectangle);
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  }

  std::string path_;
};

#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(GmshReaderTest, RectangleQuad4) {
  const Mesh mesh = read_gmsh(kRectangle);
  EXPECT_EQ(mesh.element_type, ElementType::quad4);
  ASSERT_EQ(mesh.nodes.size(), 6u);
  ASSERT_EQ(mesh.elements.size(), 2u);
  // Node tags 1 2 3 4 5 10 become 0..5 in file order.
  EXPECT_EQ(mesh.nodes[4], Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(mesh.nodes[5], Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(mesh.elements[0], (std::vector<int>{0, 4, 5, 3}));
  EXPECT_EQ(mesh.elements[1], (std::vector<int>{4, 1, 2, 5}));

  EXPECT_EQ(mesh.node_sets.size(), 3u);
  EXPECT_EQ(mesh.node_sets.at("bottom"), (std::vector<int>{0, 1, 4}));
  EXPECT_EQ(mesh.node_sets.at("top"), (std::vector<int>{2, 3, 5}));
  EXPECT_EQ(mesh.node_sets.at("body"), (std::vector<int>{0, 1, 2, 3, 4, 5}));
  ASSERT_EQ(mesh.face_sets.size(), 2u);  // the surface group gives nodes only
  const std::vector<Face>& bottom = mesh.face_sets.at("bottom");
  const std::vector<Face>& top = mesh.face_sets.at("top");
  ASSERT_EQ(bottom.size(), 2u);
  ASSERT_EQ(top.size(), 2u);
  for (int e = 0; e < 2; ++e) {
    EXPECT_EQ(bottom[e].element, e);
    EXPECT_EQ(bottom[e].local_face, 0);
    EXPECT_EQ(top[e].element, e);
    EXPECT_EQ(top[e].local_face, 2);
  }
  // Outward normal (t_y, −t_x): down on "bottom", up on "top", whatever the lines' direction in the file.
  for (const Face& face : bottom) {
    const Eigen::Vector3d t = mesh.nodes[face.nodes[1]] - mesh.nodes[face.nodes[0]];
    EXPECT_EQ(Eigen::Vector3d(t.y(), -t.x(), 0.0), Eigen::Vector3d(0, -1, 0));
  }
  for (const Face& face : top) {
    const Eigen::Vector3d t = mesh.nodes[face.nodes[1]] - mesh.nodes[face.nodes[0]];
    EXPECT_EQ(Eigen::Vector3d(t.y(), -t.x(), 0.0), Eigen::Vector3d(0, 1, 0));
  }
}

TEST(GmshReaderTest, CubeHexa8) {
  const Mesh mesh = read_gmsh(kCube);
  EXPECT_EQ(mesh.element_type, ElementType::hexa8);
  ASSERT_EQ(mesh.nodes.size(), 8u);
  ASSERT_EQ(mesh.elements.size(), 1u);
  EXPECT_EQ(mesh.elements[0], (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(mesh.nodes[6], Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(mesh.node_sets.size(), 1u);
  EXPECT_EQ(mesh.node_sets.at("base"), (std::vector<int>{0, 1, 2, 3}));
  ASSERT_EQ(mesh.face_sets.at("base").size(), 1u);
  const Face& base = mesh.face_sets.at("base")[0];
  EXPECT_EQ(base.element, 0);
  EXPECT_EQ(base.local_face, 0);
  // The file's quadrangle runs 1 2 3 4 (normal +z); the face set takes the outward order (normal −z).
  const auto& x = mesh.nodes;
  const Eigen::Vector3d normal = (x[base.nodes[1]] - x[base.nodes[0]]).cross(x[base.nodes[3]] - x[base.nodes[0]]);
  EXPECT_EQ(normal, Eigen::Vector3d(0, 0, -1));
}

TEST(GmshReaderTest, MissingFile) {
  const std::string path = kDataDirectory + "no_such_mesh.msh";
  try {
    read_gmsh(path);
    FAIL() << "no FemError";
  } catch (const FemError& error) {
    const std::string message = error.what();
    EXPECT_CONTAINS(message, "cannot open");
    EXPECT_CONTAINS(message, path);
  }
}

// Refused before opening: a directory read as an empty file, a device without end.
TEST(GmshReaderTest, NotARegularFile) {
  for (const std::string& path : {kDataDirectory, std::string("/dev/zero")}) {
    try {
      read_gmsh(path);
      ADD_FAILURE() << path << ": no FemError";
    } catch (const FemError& error) {
      EXPECT_EQ(std::string(error.what()),
                path + ": not a regular file (a directory, a FIFO or a device holds no Gmsh mesh)");
    }
  }
}

TEST_F(MalformedGmshTest, WrongVersion) {
  const std::string message = error_reading(rectangle_with("4.1 0 8", "2.2 0 8"));
  EXPECT_CONTAINS(message, path_ + ":2:");
  EXPECT_CONTAINS(message, "only MSH 4.1 ASCII is supported");
}

TEST_F(MalformedGmshTest, BinaryFlag) {
  const std::string message = error_reading(rectangle_with("4.1 0 8", "4.1 1 8"));
  EXPECT_CONTAINS(message, path_ + ":2:");
  EXPECT_CONTAINS(message, "binary");
  EXPECT_CONTAINS(message, "only MSH 4.1 ASCII is supported");
}

TEST_F(MalformedGmshTest, Truncated) {
  const std::string text = file_text(kRectangle);
  const std::string message = error_reading(text.substr(0, text.find("1 3 0 1\n10")));
  EXPECT_CONTAINS(message, path_ + ":");
  EXPECT_CONTAINS(message, "unexpected end of file");
}

TEST_F(MalformedGmshTest, MissingSection) {
  const std::string text = file_text(kRectangle);
  const std::string message = error_reading(text.substr(0, text.find("$Elements")));
  EXPECT_CONTAINS(message, path_ + ":");
  EXPECT_CONTAINS(message, "missing section $Elements");
}

TEST_F(MalformedGmshTest, UnknownNodeTag) {
  const std::string text = rectangle_with("6 5 2 3 10", "6 5 2 3 11");
  const std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "6 5 2 3 11")) + ":");
  EXPECT_CONTAINS(message, "unknown node tag 11");
}

TEST_F(MalformedGmshTest, UnreadableNumber) {
  const std::string text = rectangle_with("\n2 0 0\n", "\n2 zero 0\n");
  const std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "2 zero 0")) + ":");
  EXPECT_CONTAINS(message, "'zero'");
}

TEST_F(MalformedGmshTest, PhysicalLineNotOnTheBoundary) {
  // The second "top" line becomes the edge between the two quadrangles, shared by both.
  const std::string text = rectangle_with("4 10 4", "4 10 5");
  const std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "4 10 5")) + ":");
  EXPECT_CONTAINS(message, "'top'");
  EXPECT_CONTAINS(message, "not a face on the boundary");
}

TEST_F(MalformedGmshTest, UnsupportedElementType) {
  const std::string text = rectangle_with("2 1 3 2", "2 1 2 2");  // triangles
  const std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "2 1 2 2")) + ":");
  EXPECT_CONTAINS(message, "element type 2");
}

TEST_F(MalformedGmshTest, MixedElementTypes) {
  // The second quadrangle becomes an 8-node one: its own corners, nodes 1 and 4, and two new nodes.
  std::string text = rectangle_with("3 6 1 6", "4 6 1 6");
  text.replace(text.find("7 6 1 10"), 8, "8 8 1 12");
  text.replace(text.find("$EndNodes"), 9, "2 1 0 2\n11\n12\n1.5 0 0\n2 0.5 0\n$EndNodes");
  const std::string quadrangles = "2 1 3 2\n5 1 5 10 4\n6 5 2 3 10\n";
  text.replace(text.find(quadrangles), quadrangles.size(), "2 1 3 1\n5 1 5 10 4\n2 1 16 1\n6 5 2 3 10 1 4 11 12\n");
  const std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "6 5 2 3 10 1 4 11 12")) + ":");
  EXPECT_CONTAINS(message, "one element type per mesh");
}

// A node listed twice: named with the element's tag and line, whatever the element type.
TEST_F(MalformedGmshTest, ElementListingANodeTwice) {
  std::string text = rectangle_with("6 5 2 3 10", "6 5 2 2 10");
  std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "6 5 2 2 10")) +
                               ": element 6 (4-node quadrangle, nodes 5 2 2 10) lists node 2 twice");

  text = file_text(kCube);
  text.replace(text.find("2 1 2 3 4 5 6 7 8"), 17, "2 1 2 3 4 5 6 7 5");
  message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "2 1 2 3 4 5 6 7 5")) +
                               ": element 2 (8-node hexahedron, nodes 1 2 3 4 5 6 7 5) lists node 5 twice");

  // The rectangle's quadrangles as one 8-node quadrangle whose mid-side node 10 is also a corner.
  text = rectangle_with("2 1 3 2\n5 1 5 10 4\n6 5 2 3 10\n", "2 1 16 1\n7 1 2 3 10 5 3 10 4\n");
  message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "7 1 2 3 10 5 3 10 4")) +
                               ": element 7 (8-node quadrangle, nodes 1 2 3 10 5 3 10 4) lists node 3 twice");
}

TEST_F(MalformedGmshTest, PlaneMeshOutOfItsPlane) {
  const std::string text = rectangle_with("\n0 1 0\n", "\n0 1 0.5\n");
  const std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":");
  EXPECT_CONTAINS(message, "z = 0");
}

// Every integer is read whole and checked against its field's range: none is narrowed to an int (an
// element type 2^32 + 3 was read as 3, an entity tag 2^32 + 1 as 1, and the meshes accepted).
TEST_F(MalformedGmshTest, IntegersOutOfTheirRange) {
  struct Case {
    const char *from, *to, *message;
  };
  const Case cases[] = {
      {"2 1 3 2\n", "2 1 4294967299 2\n", "the element type of an element block 4294967299 is out of range"},
      {"2 1 3 2\n", "2 4294967297 3 2\n", "the entity tag of an element block 4294967297 is out of range"},
      {"1 0 0 0 2 1 0 1 3 4", "4294967297 0 0 0 2 1 0 1 3 4", "an entity tag 4294967297 is out of range"},
      {"1 0 0 0 2 1 0 1 3 4", "1 0 0 0 2 1 0 1 4294967299 4", "a physical tag 4294967299 is out of range"},
      {"2 3 \"body\"", "2 4294967299 \"body\"", "a physical tag 4294967299 is out of range"},
      {"2 3 \"body\"", "4 3 \"body\"", "a physical group dimension 4 is out of range [0, 3]"},
      {"\n1 1 0 1\n5\n", "\n5 1 0 1\n5\n", "the entity dimension of a node block 5 is out of range [0, 3]"},
      {"\n0 1 0 1\n1\n", "\n0 1 2 1\n1\n", "the parametric flag of a node block 2 is out of range [0, 1]"},
      {"\n0 1 0 1\n1\n", "\n0 4294967297 0 1\n1\n", "the entity tag of a node block 4294967297 is out of range"},
      {"5 1 5 10 4", "0 1 5 10 4", "an element tag 0 is out of range [1, "},
      {"5 1 5 10 4", "5 1 5 10 -4", "an element node tag -4 is out of range [1, "},
      {"5 1 5 10 4", "5 1 5 10 18446744073709551620", "an element node tag 18446744073709551620 is out of range"},
      {"\n3 6 1 6\n", "\n3 4294967302 1 6\n", "the number of elements 4294967302 is out of range"},
      {"4.1 0 8", "4.1 0 -8", "the MSH data size -8 is out of range"},
  };
  for (const Case& c : cases) {
    const std::string text = rectangle_with(c.from, c.to);
    const std::string message = error_reading(text);
    const std::string changed = std::string(c.to).substr(std::string(c.to).find_first_not_of('\n'));
    EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, changed)) + ": " + c.message);
  }
}

// A count is not believed beyond what the file can hold: announcing two billion nodes or elements in a
// small file is a mismatch named with its line, not an allocation of 80 GB.
TEST_F(MalformedGmshTest, HugeAnnouncedCountsAreMismatches) {
  std::string message = error_reading(rectangle_with("\n7 6 1 10\n", "\n7 2000000000 1 10\n"));
  EXPECT_CONTAINS(message, "$Nodes announces 2000000000 nodes, its blocks hold 6");
  message = error_reading(rectangle_with("\n3 6 1 6\n", "\n3 2000000000 1 6\n"));
  EXPECT_CONTAINS(message, "$Elements announces 2000000000 elements, its blocks hold 6");
}

// A token is quoted to its first 40 characters in a message, with its length: not a megabyte of it.
TEST_F(MalformedGmshTest, LongTokenQuotedShort) {
  const std::string token = "7" + std::string(1 << 20, 'x');
  const std::string text = rectangle_with("\n2 0 0\n", "\n2 " + token + " 0\n");
  const std::string message = error_reading(text);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "\n2 7x") + 1) + ": expected a finite number");
  EXPECT_CONTAINS(message, "'" + token.substr(0, 40) + "… (" + std::to_string(token.size()) + " characters)'");
  EXPECT_LT(message.size(), 300u);
}

// A file of zeros, or a NUL byte in a text: binary, named with its line and column, not "empty".
TEST_F(MalformedGmshTest, NulBytesAreNotText) {
  std::string message = error_reading(std::string(4096, '\0'));
  EXPECT_CONTAINS(message, path_ + ":1: byte 0x00 (NUL) at column 1: not a text file");

  const std::string text = rectangle_with("\n2 0 0\n", "\n2 0 0\n");
  std::string with_nul = text;
  with_nul.insert(with_nul.find("\n2 0 0\n") + 4, 1, '\0');  // "2 0" NUL " 0": column 4
  message = error_reading(with_nul);
  EXPECT_CONTAINS(message, path_ + ":" + std::to_string(line_of(text, "\n2 0 0\n") + 1) +
                               ": byte 0x00 (NUL) at column 4: not a text file");
}

// The file is read as a stream: a section the reader skips (32 MB in 512 Ki lines here) does not stay in
// memory. The process' peak resident size may grow by far less than the section (it held every line of
// the file, 57 MB for this one, before).
TEST_F(MalformedGmshTest, FileIsNotHeldInMemory) {
  write(file_text(kRectangle));
  {  // written line by line: the test itself must not hold the file either
    std::ofstream file(path_, std::ios::app);
    file << "$Comments\n";
    const std::string line(63, 'c');
    for (int i = 0; i < (1 << 19); ++i) file << line << '\n';
    file << "$EndComments\n";
  }
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  const long before = usage.ru_maxrss;  // KiB
  const Mesh mesh = read_gmsh(path_);
  ::getrusage(RUSAGE_SELF, &usage);
  EXPECT_EQ(mesh.elements.size(), 2u);
  EXPECT_LT(usage.ru_maxrss - before, 8 * 1024) << "KiB of peak resident size gained while reading";
}

}  // namespace
}  // namespace csim
