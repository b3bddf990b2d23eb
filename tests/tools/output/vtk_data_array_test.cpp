// The encodings of the ParaView files (tools/output/vtk_data_array.h, output.paraview): every file of a
// run read back through vtu_reader.h (appended offsets, VTK's compression header, array lengths against
// the piece's counts), and the binary and zlib runs holding exactly the ASCII run's values: an elastic
// shoe in QUAD4 with contacts, a finite-strain pendulum (with its strain array), a HEXA8 block under a
// box. The reader itself must refuse a broken offset, a truncated block and a wrong array length.
#include "tools/output/atomic_file.h"
#include "tools/output/vtk_data_array.h"
#include "tools/output/vtk_writer.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "tests/tools/output/vtu_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace csim {
namespace {

namespace fs = std::filesystem;
using test_xml::XmlElement;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The same tree: names, attributes (but format and offset, which the encoding sets) and, for each
// DataArray, the same numbers, bit for bit (the ASCII text is the shortest that reads back exactly).
void expect_same_content(const XmlElement& ascii, const XmlElement& other, const std::string& where) {
  ASSERT_EQ(ascii.name, other.name) << where;
  auto a = ascii.attributes, b = other.attributes;
  for (auto* attributes : {&a, &b})
    for (const char* key : {"format", "offset", "compressor"}) attributes->erase(key);
  EXPECT_EQ(a, b) << where << " <" << ascii.name << ">";
  if (ascii.name == "DataArray") {
    const std::vector<double> x = ascii.numbers(), y = other.numbers();
    ASSERT_EQ(x.size(), y.size()) << where;
    for (std::size_t i = 0; i < x.size(); ++i)
      ASSERT_EQ(x[i], y[i]) << where << " " << (a.count("Name") ? a.at("Name") : "points") << "[" << i << "]";
    return;
  }
  ASSERT_EQ(ascii.children.size(), other.children.size()) << where << " <" << ascii.name << ">";
  for (std::size_t i = 0; i < ascii.children.size(); ++i) expect_same_content(ascii.children[i], other.children[i], where);
}

std::vector<VtkEncoding> all_encodings() {
  std::vector<VtkEncoding> out{VtkEncoding::ascii, VtkEncoding::binary};
  if (vtk_compression_available()) out.push_back(VtkEncoding::zlib);
  return out;
}

struct EncodedRun {
  const char* scene;
  std::vector<std::string> overrides;
};

void PrintTo(const EncodedRun& run, std::ostream* out) { *out << run.scene; }

class EncodedRuns : public ::testing::TestWithParam<EncodedRun> {};

TEST_P(EncodedRuns, BinaryAndRawFilesHoldTheAsciiValues) {
  const EncodedRun& param = GetParam();
  const std::string scene_file = CSIM_SOURCE_DIR "/scenes/" + std::string(param.scene) + "/scene.yaml";
  std::map<std::string, fs::path> folders;
  std::vector<std::string> encodings{"ascii", "binary"};
  if (vtk_compression_available()) encodings.push_back("zlib");
  for (const std::string& encoding : encodings) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("csim_vtk_encoding_" + std::string(param.scene) + "_" + encoding);
    fs::remove_all(dir);
    std::vector<std::string> overrides = param.overrides;
    overrides.push_back("output.paraview=" + std::string(encoding));
    const auto scene = load_scene(scene_file, overrides);
    run_scene(*scene, {dir.string()});
    folders[encoding] = dir / "paraview";
  }
  std::size_t files = 0, contact_points = 0, strain_arrays = 0;
  std::uintmax_t bytes_binary = 0, bytes_zlib = 0;
  for (const auto& entry : fs::directory_iterator(folders["ascii"])) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".pvd") {  // the collections do not depend on the encoding
      for (const std::string& encoding : encodings)
        EXPECT_EQ(read_text(entry.path()), read_text(folders[encoding] / name)) << encoding << " " << name;
      continue;
    }
    ASSERT_EQ(entry.path().extension(), ".vtu") << name;
    ++files;
    const test_vtu::VtuFile ascii = test_vtu::read_vtu(read_text(entry.path()));
    EXPECT_FALSE(ascii.appended) << name;
    for (const std::string encoding : {"binary", "zlib"}) {
      if (!folders.count(encoding)) continue;
      const test_vtu::VtuFile other = test_vtu::read_vtu(read_text(folders[encoding] / name));
      EXPECT_TRUE(other.appended) << encoding << " " << name;
      EXPECT_EQ(other.compressed, encoding == "zlib") << encoding << " " << name;
      EXPECT_EQ(ascii.comments, other.comments) << encoding << " " << name;
      expect_same_content(ascii.root, other.root, name + " (" + encoding + ")");
    }
    const XmlElement& piece = ascii.root.child("UnstructuredGrid").child("Piece");
    if (name.rfind("contacts_", 0) == 0) contact_points += std::stoul(piece.attributes.at("NumberOfPoints"));
    else {
      bytes_binary += fs::file_size(folders["binary"] / name);
      if (folders.count("zlib")) bytes_zlib += fs::file_size(folders["zlib"] / name);
      for (const XmlElement& array : piece.child("CellData").children)
        if (array.attributes.at("Name") == "green_lagrange_strain") ++strain_arrays;
    }
    if (HasFailure()) return;  // one file's report is enough
  }
  std::printf("[ measured ] %s: %zu files, %zu contact points, %zu strain arrays; body files binary %ju B, zlib %ju B\n",
              param.scene, files, contact_points, strain_arrays, bytes_binary, bytes_zlib);
  EXPECT_GE(files, 4u);
  if (std::string(param.scene) == "tied-pendulum") {
    EXPECT_GT(strain_arrays, 0u);
  } else {
    EXPECT_GT(contact_points, 0u);  // the contacts' arrays are compared too
  }
  if (vtk_compression_available()) {
    EXPECT_LT(bytes_zlib, bytes_binary);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, EncodedRuns,
    ::testing::Values(EncodedRun{"sdnv104-quad4", {"time.end=0.005", "output.rate=0.001"}},
                      EncodedRun{"tied-pendulum", {"time.end=0.01", "output.rate=0.002"}},
                      EncodedRun{"box-on-block-3d", {"time.end=0.03", "output.rate=0.005"}}),
    [](const auto& info) {
      std::string name = info.param.scene;
      for (char& c : name)
        if (c == '-') c = '_';
      return name;
    });

// An array longer than a compression block (32 KiB = 4096 doubles), and one that fills whole blocks,
// read back exactly.
TEST(VtkDataArray, ArraysOfSeveralBlocksReadBack) {
  for (const std::size_t count : {std::size_t{4096}, std::size_t{3 * 4096}, std::size_t{10000}}) {
    std::vector<double> values(count);
    for (std::size_t i = 0; i < count; ++i) values[i] = std::sin(0.001 * i) * 1e3 + (i % 7 == 0 ? 0.0 : 1.0 / (i + 1));
    for (const VtkEncoding encoding : all_encodings()) {
      VtkFileText file(encoding);
      file.open("UnstructuredGrid", "");
      file.xml() += "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" + std::to_string(count) +
                    "\" NumberOfCells=\"0\">\n      <PointData>\n";
      file.array(encode_array(encoding, "Float64", "f", 1, values));
      file.xml() += "      </PointData>\n    </Piece>\n  </UnstructuredGrid>\n";
      const test_vtu::VtuFile read = test_vtu::read_vtu(file.finish());
      const std::vector<double> back =
          read.root.child("UnstructuredGrid").child("Piece").child("PointData").array("f").numbers();
      EXPECT_EQ(back, values) << count << " values, encoding " << static_cast<int>(encoding);
    }
  }
}

// A frame streamed to its file (VtkFileText::write, as ParaviewSeries writes a body's frames) holds the
// bytes of the assembled text, in every encoding, and write_file_atomically puts them in place whole.
TEST(VtkDataArray, StreamedFileIsTheAssembledText) {
  Mesh mesh;
  mesh.element_type = ElementType::quad4;
  mesh.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  mesh.elements = {{0, 1, 2, 3}, {1, 4, 5, 2}};
  ElementFields fields;
  fields.stress = {Stress::Constant(2.0), Stress::LinSpaced(-1.0, 4.0)};
  const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(12, -0.5, 1.0);
  const fs::path folder = fs::temp_directory_path() / "csim-streamed-vtu";
  fs::create_directories(folder);
  for (const VtkEncoding encoding : all_encodings()) {
    const EncodedMesh encoded = encode_mesh(mesh, encoding);
    VtkFileText file(encoding);
    fe_body_file(file, encoded, u, 2.0 * u, fields, 0.25);
    std::ostringstream streamed;
    file.write(streamed);
    const std::string text = file.finish();
    EXPECT_EQ(streamed.str(), text) << "encoding " << static_cast<int>(encoding);
    EXPECT_EQ(text, fe_body_vtu(mesh, u, 2.0 * u, fields, 0.25, encoding));
    const fs::path path = folder / "body.vtu";
    write_file_atomically(path.string(), [&file](std::ostream& out) { file.write(out); });
    EXPECT_EQ(read_text(path), text);
    EXPECT_NO_THROW(test_vtu::read_vtu(read_text(path)));
  }
  fs::remove_all(folder);
}

// A writer that fails midway leaves neither the file nor its temporary.
TEST(VtkDataArray, FailedStreamLeavesNoFile) {
  const fs::path folder = fs::temp_directory_path() / "csim-failed-vtu";
  fs::create_directories(folder);
  const fs::path path = folder / "body.vtu";
  EXPECT_THROW(write_file_atomically(path.string(),
                                     [](std::ostream& out) {
                                       out << "<?xml version=\"1.0\"?>\n";
                                       throw std::runtime_error("encoding failed");
                                     }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(folder / "body.vtu.tmp"));
  fs::remove_all(folder);
}

// The read-back tests can fail: a file with a broken offset, a truncated block or a short array is
// refused by the reader.
TEST(VtkDataArray, ReaderRefusesBrokenFiles) {
  Mesh mesh;
  mesh.element_type = ElementType::quad4;
  mesh.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.elements.push_back({0, 1, 2, 3});
  ElementFields fields;
  fields.stress.push_back(Stress::Constant(2.0));
  const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(8, 0.0, 1.0);
  for (const VtkEncoding encoding : all_encodings()) {
    if (encoding == VtkEncoding::ascii) continue;
    const std::string good = fe_body_vtu(mesh, u, u, fields, 0.5, encoding);
    EXPECT_NO_THROW(test_vtu::read_vtu(good));

    std::string offset = good;  // the velocity's offset moved by one byte
    const std::size_t velocity = offset.find("Name=\"velocity\"");
    const std::size_t digits = offset.find("offset=\"", velocity) + 8;
    offset.insert(digits, "1");
    EXPECT_THROW(test_vtu::read_vtu(offset), std::runtime_error) << "offset";

    std::string truncated = good;  // one byte of the appended data lost
    truncated.erase(truncated.find("\n  </AppendedData>") - 1, 1);
    EXPECT_THROW(test_vtu::read_vtu(truncated), std::runtime_error) << "truncated";

    std::string count = good;  // the piece claims a fifth point
    count.replace(count.find("NumberOfPoints=\"4\""), 18, "NumberOfPoints=\"5\"");
    EXPECT_THROW(test_vtu::read_vtu(count), std::runtime_error) << "count";
  }
}

}  // namespace
}  // namespace csim
