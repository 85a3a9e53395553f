// What the per-format files add to the contract in mesh_io_test.cpp: VTP through a real XML
// parser (expat), gmsh MSH as a surface format, and the one MSH parser's count checks.
#include "geometry/mesh_io.h"
#include "geometry/mesh_io_msh.h"
#include "geometry/xml_tree.h"

#include "core/error.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>

namespace hipfai::geometry {
namespace {

namespace fs = std::filesystem;

// Files under the build tree's scratch folder, one folder per test (kept for inspection).
class MeshIoFormatsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / "mesh_io_formats" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }

  fs::path write_bytes(const std::string& filename, const std::string& bytes) const {
    std::ofstream(dir_ / filename, std::ios::binary) << bytes;
    return dir_ / filename;
  }

  // The hipfai::Error message of reading `path` ("" and a failure when it reads).
  static std::string read_error(const fs::path& path) {
    std::string message;
    EXPECT_THROW(
        try { read_mesh(path); } catch (const Error& e) {
          message = e.what();
          throw;
        },
        Error);
    return message;
  }

  fs::path dir_;
};

// One triangle, ascii arrays; `points` is the Points DataArray's content.
std::string vtp_triangle(const std::string& points) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\">\n<PolyData>\n"
         "<Piece NumberOfPoints=\"3\" NumberOfPolys=\"1\">\n"
         "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">" +
         points +
         "</DataArray></Points>\n"
         "<Polys><DataArray type=\"Int32\" Name=\"connectivity\">0 1 2</DataArray>"
         "<DataArray type=\"Int32\" Name=\"offsets\">3</DataArray></Polys>\n"
         "</Piece>\n</PolyData>\n</VTKFile>\n";
}

// ---- VTP through expat

TEST_F(MeshIoFormatsTest, MalformedXmlIsOneLineWithLineAndColumn) {
  // </Points> closes <DataArray>: the XML parser, not a guess, finds the mismatch on line 5.
  std::string text = vtp_triangle("0 0 0 1 0 0 0 1 0");
  text.replace(text.find("</DataArray></Points>"), 12, "");
  const std::string message = read_error(write_bytes("bad.vtp", text));
  EXPECT_NE(message.find("bad.vtp: malformed XML at line 5, column"), std::string::npos) << message;
  EXPECT_NE(message.find("mismatched tag"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST_F(MeshIoFormatsTest, EmptyAndNonXmlFilesAreMalformed) {
  EXPECT_NE(read_error(write_bytes("empty.vtp", "")).find("malformed XML"), std::string::npos);
  EXPECT_NE(read_error(write_bytes("text.vtp", "solid x\n")).find("malformed XML"), std::string::npos);
}

TEST_F(MeshIoFormatsTest, CdataCommentsAndEntitiesAreXml) {
  // Valid XML the old hand-written scanner did not take: data in CDATA, a comment inside the
  // array, a character reference in the text.
  const TriMesh mesh = read_mesh(write_bytes(
      "cdata.vtp", vtp_triangle("<![CDATA[0 0 0 1 0 0]]><!-- third point: --> 0 &#49; 0")));
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.vertices[1], Vec3(1, 0, 0));
  EXPECT_EQ(mesh.vertices[2], Vec3(0, 1, 0));
}

TEST_F(MeshIoFormatsTest, RawAppendedDataIsRejectedForWhatItIs) {
  // Raw appended bytes are not XML; the reader stops at <AppendedData> and says why.
  std::string text = vtp_triangle("0 0 0 1 0 0 0 1 0");
  text.insert(text.find("</VTKFile>"), "<AppendedData encoding=\"raw\">_\x01\x02<\xff&\x00\x03</AppendedData>\n");
  const std::string message = read_error(write_bytes("raw.vtp", text));
  EXPECT_NE(message.find("appended data (<AppendedData>) is not supported"), std::string::npos) << message;
}

TEST_F(MeshIoFormatsTest, VtpFieldNamesWithXmlCharactersRoundTrip) {
  TriMesh mesh = make_box(Vec3::Zero(), Vec3::Ones(), 1);
  mesh.vertex_fields["a<b & \"c\""] = std::vector<double>(mesh.num_vertices(), 0.5);
  for (const bool ascii : {true, false}) {
    write_mesh(mesh, dir_ / "names.vtp", MeshWriteOptions{ascii});
    const TriMesh back = read_mesh(dir_ / "names.vtp");
    ASSERT_EQ(back.vertex_fields.count("a<b & \"c\""), 1u) << (ascii ? "ascii" : "binary");
    EXPECT_EQ(back.vertex_fields.at("a<b & \"c\""), mesh.vertex_fields.at("a<b & \"c\""));
  }
}

TEST(XmlTree, AStartTagHandlerThatThrowsStopsTheParse) {
  int seen = 0;
  auto count_then_stop = [&seen](const XmlElement& element) {
    ++seen;
    if (element.name == "stop") throw std::runtime_error("stop here");
  };
  // Nothing after <stop> is read: the bytes after it are not even well-formed.
  EXPECT_THROW(parse_xml("x", "<a><b/><stop>\x01<<<", count_then_stop), std::runtime_error);
  EXPECT_EQ(seen, 3);
  const auto root = parse_xml("x", "<a k='1 &lt; 2'>t<b/>u</a>");
  EXPECT_EQ(root->attribute("k"), "1 < 2");
  EXPECT_EQ(root->attribute("missing", "none"), "none");
  EXPECT_EQ(root->text, "tu");
  ASSERT_EQ(root->children.size(), 1u);
  EXPECT_EQ(root->children[0]->name, "b");
}

// ---- gmsh MSH as a surface format

TEST_F(MeshIoFormatsTest, MshSurfaceRoundTripIsExact) {
  const TriMesh mesh = make_box(Vec3(0.1, -2.0, 3.0), Vec3(1.7, 0.3, 4.0 / 3.0 + 3.0), 2);
  write_mesh(mesh, dir_ / "box.msh");
  const TriMesh back = read_mesh(dir_ / "box.msh");
  EXPECT_EQ(back.vertices, mesh.vertices);  // shortest round-trip decimals: bit for bit
  EXPECT_EQ(back.triangles, mesh.triangles);
  EXPECT_EQ(to_string(mesh_format_from_path("A.MSH")), "MSH");
}

TEST_F(MeshIoFormatsTest, MshReadsWhatGmshWritesForASurface) {
  // As gmsh -2 -format msh22 writes it: points and lines besides the surface, node ids that do
  // not start at 1, a node only a line uses, a quadrangle, and a $NodeData section.
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
      "$PhysicalNames\n1\n2 7 \"bone surface\"\n$EndPhysicalNames\n"
      "$Nodes\n6\n10 0 0 0\n11 1 0 0\n12 1 1 0\n13 0 1 0\n14 5 5 5\n15 0.5 0.5 1\n$EndNodes\n"
      "$Elements\n5\n1 15 2 0 1 10\n2 1 2 0 1 10 14\n3 3 2 7 1 10 11 12 13\n4 2 2 7 1 10 11 15\n"
      "5 2 2 7 1 12 13 15\n$EndElements\n"
      "$NodeData\n1\n\"t\"\n1\n0.0\n3\n0\n1\n6\n10 1\n11 1\n12 1\n13 1\n14 1\n15 1\n$EndNodeData\n";
  const TriMesh mesh = read_mesh(write_bytes("gmsh.msh", text));
  EXPECT_EQ(mesh.vertices.size(), 5u);  // node 14 belongs to a line only
  ASSERT_EQ(mesh.triangles.size(), 4u);  // the quadrangle as two, then the two triangles
  EXPECT_EQ(mesh.vertices[mesh.triangles[2][2]], Vec3(0.5, 0.5, 1));
  EXPECT_EQ(mesh.vertices[4], Vec3(0.5, 0.5, 1));  // file order kept, node 14 left out
  const mesh_io::MshMesh msh = mesh_io::parse_msh("gmsh.msh", text);
  ASSERT_EQ(msh.physical_names.size(), 1u);
  EXPECT_EQ(msh.physical_names[0].name, "bone surface");
  EXPECT_EQ(msh.elements[2].id, 3);
  EXPECT_EQ(msh.elements[2].physical, 7);
}

TEST_F(MeshIoFormatsTest, MshCountsBeyondTheFileAreErrorsNotAllocations) {
  const std::string header = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  EXPECT_NE(read_error(write_bytes("n.msh", header + "$Nodes\n999999999999\n1 0 0 0\n$EndNodes\n"))
                .find("truncated $Nodes: 999999999999 declared"),
            std::string::npos);
  EXPECT_NE(read_error(write_bytes("e.msh", header + "$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n-3\n"))
                .find("truncated $Elements: -3 declared"),
            std::string::npos);
  EXPECT_NE(read_error(write_bytes("b.msh", "$MeshFormat\n2.2 1 8\n$EndMeshFormat\n")).find("not an ASCII MSH 2.2"),
            std::string::npos);
  EXPECT_NE(read_error(write_bytes("t.msh", header + "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                                                     "$Elements\n1\n1 9 2 0 1 1 2 3 1 2 3\n$EndElements\n"))
                .find("element 1 has type 9"),
            std::string::npos);
}

// As the contract test does for the other formats: prefixes and single-byte corruptions of a
// valid .msh either read or throw hipfai::Error, never another exception or a crash.
TEST_F(MeshIoFormatsTest, TruncatedAndCorruptedMshOnlyEverThrowsError) {
  write_mesh(make_box(Vec3::Zero(), Vec3::Ones(), 1), dir_ / "source.msh");
  std::ifstream in(dir_ / "source.msh", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::mt19937 random(20261124);
  std::size_t errors = 0, attempts = 0;
  auto attempt = [&](const std::string& variant) {
    const fs::path path = write_bytes("variant" + std::to_string(++attempts) + ".msh", variant);
    try {
      read_mesh(path);
    } catch (const Error&) {
      ++errors;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "variant " << attempts << ": " << e.what();
    }
    fs::remove(path);
  };
  for (std::size_t length = 0; length < bytes.size(); length += 7) attempt(bytes.substr(0, length));
  for (int trial = 0; trial < 200; ++trial) {
    std::string variant = bytes;
    variant[random() % variant.size()] = static_cast<char>(random() % 256);
    attempt(variant);
  }
  EXPECT_GT(errors, attempts / 2);  // most variants are broken; the reader must have noticed
}

}  // namespace
}  // namespace hipfai::geometry

namespace hipfai::geometry {
namespace {

// Inputs the fuzzer found in the mesh readers (scripts/fuzz, tests/data/fuzz-regressions/<format>/):
// each must give a one-line hipfai::Error at once. element_without_properties.ply: a binary PLY
// declaring about 1.8e11 records of an element with no properties (took seconds of empty loop per
// read).
TEST(MeshIoFuzzRegressions, EveryFoundInputIsAOneLineError) {
  const std::filesystem::path dir = std::filesystem::path(HIPFAI_SOURCE_DIR) / "tests/data/fuzz-regressions";
  int inputs = 0;
  for (const char* format : {"stl", "ply", "obj", "vtp", "msh"}) {
    if (!std::filesystem::is_directory(dir / format)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir / format)) {
      ++inputs;
      try {
        (void)read_mesh(entry.path());
        ADD_FAILURE() << entry.path() << ": read without an error";
      } catch (const Error& error) {
        EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
      }
    }
  }
  EXPECT_GE(inputs, 1);
}

}  // namespace
}  // namespace hipfai::geometry
