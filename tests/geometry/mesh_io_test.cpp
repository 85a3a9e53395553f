#include "geometry/mesh_io.h"

#include "core/error.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>

namespace hipfai::geometry {
namespace {

namespace fs = std::filesystem;

// A scratch folder per test, removed afterwards.
class MeshIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("hipfai_mesh_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write_bytes(const std::string& filename, const std::string& bytes) const {
    const fs::path path = dir_ / filename;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  // Runs read_mesh and returns the hipfai::Error message; fails the test if nothing is thrown.
  static std::string read_error(const fs::path& path) {
    try {
      read_mesh(path);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no hipfai::Error reading " << path;
    return "";
  }

  fs::path dir_;
};

// Corner positions of every triangle: equal for two meshes that describe the same surface with
// the same triangle order, whatever their vertex numbering.
std::vector<std::array<Vec3, 3>> corners(const TriMesh& mesh) {
  std::vector<std::array<Vec3, 3>> out;
  for (const Triangle& tri : mesh.triangles) {
    out.push_back({mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]});
  }
  return out;
}

// The test box: every coordinate is a multiple of 1/4, exact in float32 and in shortest decimal
// text, so every format (STL stores float32) must reproduce it bit for bit.
TriMesh box_with_field() {
  TriMesh mesh = make_box(Vec3(-1.0, 0.0, 2.0), Vec3(1.0, 2.5, 3.0), 4);
  std::vector<double>& depth = mesh.vertex_fields["depth_mm"];
  std::vector<double>& pressure = mesh.vertex_fields["pressure_MPa"];
  for (const Vec3& p : mesh.vertices) {
    depth.push_back(std::sqrt(2.0) * p.x() + 1e-300);  // not short in decimal: precision check
    pressure.push_back(p.y() * p.z() / 3.0);
  }
  return mesh;
}

struct RoundTripCase {
  const char* extension;
  bool ascii;
  bool keeps_fields;
  bool keeps_indices;  // STL re-welds, which may renumber vertices
};

class RoundTrip : public MeshIoTest, public ::testing::WithParamInterface<RoundTripCase> {};

TEST_P(RoundTrip, ReproducesTheMeshExactly) {
  const RoundTripCase& c = GetParam();
  const TriMesh original = box_with_field();
  const fs::path path = dir_ / (std::string("box") + c.extension);
  write_mesh(original, path, MeshWriteOptions{c.ascii});
  const TriMesh back = read_mesh(path);
  ASSERT_EQ(back.num_triangles(), original.num_triangles());
  // Welding must recover the shared vertices: a closed box grid has 6 n^2 + 2 of them.
  EXPECT_EQ(back.num_vertices(), original.num_vertices());
  EXPECT_EQ(corners(back), corners(original));
  if (c.keeps_indices) {
    EXPECT_EQ(back.triangles, original.triangles);
  }
  if (c.keeps_fields) {
    EXPECT_EQ(back.vertex_fields, original.vertex_fields);  // bit-exact doubles
  } else {
    EXPECT_TRUE(back.vertex_fields.empty());
  }
  // Nothing but the target is left in the folder (no temporary files).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

INSTANTIATE_TEST_SUITE_P(
    Formats, RoundTrip,
    ::testing::Values(RoundTripCase{".stl", false, false, false}, RoundTripCase{".stl", true, false, false},
                      RoundTripCase{".obj", true, false, true}, RoundTripCase{".ply", false, true, true},
                      RoundTripCase{".ply", true, true, true}, RoundTripCase{".vtp", false, true, true},
                      RoundTripCase{".vtp", true, true, true}),
    [](const auto& param_info) {
      return std::string(param_info.param.extension + 1) +
             (param_info.param.ascii ? "_ascii" : "_binary");
    });

TEST_F(MeshIoTest, ExtensionIsCaseInsensitive) {
  const TriMesh box = make_box(Vec3::Zero(), Vec3::Ones(), 1);
  write_mesh(box, dir_ / "box.StL");
  EXPECT_EQ(read_mesh(dir_ / "box.StL").num_triangles(), 12u);
  EXPECT_EQ(mesh_format_from_path("A.PLY"), MeshFormat::ply);
  EXPECT_EQ(mesh_format_from_path("a.Vtp"), MeshFormat::vtp);
}

// Binary STL whose 80-byte header starts with "solid", as several CAD exporters write it.
TEST_F(MeshIoTest, BinaryStlStartingWithSolid) {
  const TriMesh box = make_box(Vec3::Zero(), Vec3(1, 2, 3), 2);
  write_mesh(box, dir_ / "plain.stl");
  std::ifstream in(dir_ / "plain.stl", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  bytes.replace(0, 11, "solid part ");
  const TriMesh back = read_mesh(write_bytes("solid.stl", bytes));
  EXPECT_EQ(corners(back), corners(box));
}

// A hand-written ASCII STL: a unit tetrahedron, solid name with spaces, CRLF line ends, and
// exponent/plus-sign number forms. Welding must give 4 shared vertices.
TEST_F(MeshIoTest, AsciiStlWeldsSharedCorners) {
  const std::string text =
      "solid my tetra\r\n"
      "facet normal 0 0 -1\r\n outer loop\r\n  vertex 0 0 0\r\n  vertex 0 1 0\r\n  vertex 1 0 0\r\n"
      " endloop\r\nendfacet\r\n"
      "facet normal 0 -1 0\r\n outer loop\r\n  vertex 0 0 0\r\n  vertex 1e0 0 0\r\n  vertex 0 0 +1\r\n"
      " endloop\r\nendfacet\r\n"
      "facet normal 1 1 1\r\n outer loop\r\n  vertex 1 0 0\r\n  vertex 0 1 0\r\n  vertex 0 0 1\r\n"
      " endloop\r\nendfacet\r\n"
      "facet normal -1 0 0\r\n outer loop\r\n  vertex 0 0 0\r\n  vertex 0 0 1\r\n  vertex 0 1 0\r\n"
      " endloop\r\nendfacet\r\n"
      "endsolid my tetra\r\n";
  const TriMesh mesh = read_mesh(write_bytes("tetra.stl", text));
  ASSERT_EQ(mesh.num_vertices(), 4u);
  ASSERT_EQ(mesh.num_triangles(), 4u);
  EXPECT_EQ(mesh.vertices[mesh.triangles[1][1]], Vec3(1, 0, 0));
  EXPECT_EQ(mesh.triangles[0][0], mesh.triangles[1][0]);  // the origin is one vertex
  EXPECT_NEAR(signed_volume(mesh), 1.0 / 6.0, 1e-15);       // exact inputs, one rounding
}

TEST_F(MeshIoTest, ObjPolygonsNegativeIndicesAndSlashForms) {
  const std::string text =
      "# unit square and a pentagon\nmtllib x.mtl\no part\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n"
      "vt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3//1 4\n"           // quad -> 2 triangles
      "v 0 0 1\nv 1 0 1\nv 1.5 0.5 1\nv 1 1 1\nv 0 1 1\n"
      "usemtl m\ns off\n"
      "f -5 -4 -3 -2 -1\n";              // pentagon -> 3 triangles, relative indices
  const TriMesh mesh = read_mesh(write_bytes("poly.obj", text));
  ASSERT_EQ(mesh.num_vertices(), 9u);
  const std::vector<Triangle> expected = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {4, 7, 8}};
  EXPECT_EQ(mesh.triangles, expected);
}

TEST_F(MeshIoTest, AsciiPlyWithIntCoordinatesExtraPropertiesAndQuads) {
  const std::string text =
      "ply\nformat ascii 1.0\ncomment quad pyramid\n"
      "element vertex 5\nproperty int x\nproperty int y\nproperty int z\nproperty float quality\n"
      "element face 5\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n"
      "0 0 0 0.5\n1 0 0 1.5\n1 1 0 2.5\n0 1 0 3.5\n0 0 1 -4\n"
      "4 3 2 1 0 7\n3 0 1 4 0\n3 1 2 4 0\n3 2 3 4 0\n3 3 0 4 0\n"
      "0 1\n";
  const TriMesh mesh = read_mesh(write_bytes("pyramid.ply", text));
  ASSERT_EQ(mesh.num_vertices(), 5u);
  ASSERT_EQ(mesh.num_triangles(), 6u);  // the quad is split in two
  EXPECT_EQ(mesh.triangles[0], (Triangle{3, 2, 1}));
  EXPECT_EQ(mesh.triangles[1], (Triangle{3, 1, 0}));
  EXPECT_EQ(mesh.vertex_fields.at("quality"), (std::vector<double>{0.5, 1.5, 2.5, 3.5, -4}));
  EXPECT_NEAR(signed_volume(mesh), 1.0 / 3.0, 1e-15);  // square base, height 1: exact inputs
}

// Big-endian binary PLY written byte by byte here, with float32 coordinates, an int list count,
// a ushort extra property and a skipped element, so the reader's swapping is checked against an
// encoding the test builds itself.
TEST_F(MeshIoTest, BinaryBigEndianPly) {
  std::string body;
  auto put_be = [&body](auto value) {
    unsigned char bytes[sizeof(value)];
    std::memcpy(bytes, &value, sizeof(value));
    if constexpr (std::endian::native == std::endian::little) std::reverse(bytes, bytes + sizeof(value));
    body.append(reinterpret_cast<const char*>(bytes), sizeof(value));
  };
  const float coords[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int v = 0; v < 4; ++v) {
    for (const float c : coords[v]) put_be(c);
    put_be(static_cast<std::uint16_t>(1000 + v));
  }
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  for (const auto& face : faces) {
    put_be(static_cast<std::int32_t>(3));
    for (const int index : face) put_be(static_cast<std::uint32_t>(index));
  }
  put_be(static_cast<std::int16_t>(-7));  // one "material" record
  const std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float32 x\n"
      "property float32 y\nproperty float32 z\nproperty ushort label\n"
      "element face 4\nproperty list int uint vertex_index\n"
      "element material 1\nproperty short id\nend_header\n";
  const TriMesh mesh = read_mesh(write_bytes("tetra.ply", header + body));
  ASSERT_EQ(mesh.num_vertices(), 4u);
  EXPECT_EQ(mesh.vertices[3], Vec3(0, 0, 1));
  EXPECT_EQ(mesh.triangles[2], (Triangle{1, 2, 3}));
  EXPECT_EQ(mesh.vertex_fields.at("label"), (std::vector<double>{1000, 1001, 1002, 1003}));
  EXPECT_NEAR(signed_volume(mesh), 1.0 / 6.0, 1e-15);
}

// Counts from the data set's description (thesis scenarios use these bones); the first vertex
// is decoded here straight from the bytes after the header, independently of the reader.
TEST_F(MeshIoTest, ReadsRealCtBones) {
  const fs::path dir = fs::path(HIPFAI_SOURCE_DIR) / "meshes/real-hips/LHDL_CT";
  const TriMesh femur = read_mesh(dir / "femur_r.ply");
  EXPECT_EQ(femur.num_vertices(), 35213u);
  EXPECT_EQ(femur.num_triangles(), 70422u);
  std::ifstream in(dir / "femur_r.ply", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t body = bytes.find("end_header\n") + 11;
  double first[3];
  std::memcpy(first, bytes.data() + body, sizeof(first));  // float64 little-endian, x86 host
  EXPECT_EQ(femur.vertices[0], Vec3(first[0], first[1], first[2]));

  const TriMesh pelvis = read_mesh(dir / "pelvis_no_sacrum.ply");
  EXPECT_EQ(pelvis.num_vertices(), 47628u);
  EXPECT_EQ(pelvis.num_triangles(), 95256u);

  // A real bone with a field survives binary VTP and PLY bit for bit.
  TriMesh with_field = femur;
  for (const Vec3& p : femur.vertices) with_field.vertex_fields["depth_mm"].push_back(p.norm() / 7.0);
  for (const char* filename : {"femur.vtp", "femur.ply"}) {
    write_mesh(with_field, dir_ / filename);
    const TriMesh back = read_mesh(dir_ / filename);
    EXPECT_EQ(back.vertices, with_field.vertices) << filename;
    EXPECT_EQ(back.triangles, with_field.triangles) << filename;
    EXPECT_EQ(back.vertex_fields, with_field.vertex_fields) << filename;
  }
}

TEST_F(MeshIoTest, VtpAsciiWithPointData) {
  const std::string text = R"(<?xml version="1.0"?>
<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">
  <!-- a <comment> with markup -->
  <PolyData>
    <Piece NumberOfPoints="4" NumberOfPolys="2">
      <PointData Scalars="t">
        <DataArray type="Float32" Name="t &amp; s" format="ascii">1 2 3 4</DataArray>
        <DataArray type="Float32" Name="normals" NumberOfComponents="3" format="ascii">
          0 0 1 0 0 1 0 0 1 0 0 1
        </DataArray>
      </PointData>
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">
          0 0 0  1 0 0  1 1 0  0 1 0
        </DataArray>
      </Points>
      <Polys>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3 0 2 1</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">4 7</DataArray>
      </Polys>
    </Piece>
  </PolyData>
</VTKFile>
)";
  const TriMesh mesh = read_mesh(write_bytes("quad.vtp", text));
  ASSERT_EQ(mesh.num_vertices(), 4u);
  const std::vector<Triangle> expected = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}};
  EXPECT_EQ(mesh.triangles, expected);
  ASSERT_EQ(mesh.vertex_fields.size(), 1u);  // the 3-component array is not a scalar field
  EXPECT_EQ(mesh.vertex_fields.at("t & s"), (std::vector<double>{1, 2, 3, 4}));
}

// A triangle strip over the unit square: every other triangle swaps its first two corners so
// all keep the winding of the first (here normal +z); Verts and Lines cells are ignored.
TEST_F(MeshIoTest, VtpStripsKeepOneWinding) {
  const std::string text =
      "<VTKFile type=\"PolyData\"><PolyData><Piece NumberOfPoints=\"4\" NumberOfStrips=\"1\">"
      "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\">0 0 0 1 0 0 0 1 0 1 1 0"
      "</DataArray></Points>"
      "<Lines><DataArray type=\"Int32\" Name=\"connectivity\">0 1</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\">2</DataArray></Lines>"
      "<Strips><DataArray type=\"Int32\" Name=\"connectivity\">0 1 2 3</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\">4</DataArray></Strips>"
      "</Piece></PolyData></VTKFile>";
  const TriMesh mesh = read_mesh(write_bytes("strip.vtp", text));
  const std::vector<Triangle> expected = {{0, 1, 2}, {2, 1, 3}};
  EXPECT_EQ(mesh.triangles, expected);
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    EXPECT_EQ(triangle_area_normal(mesh, t), Vec3(0, 0, 1)) << t;  // exact: unit right triangles
  }
}

// The base64 strings were made with Python's struct + base64 modules (see each comment), so the
// decoder is checked against an independent encoder.
std::string vtp_tetra(const std::string& file_attributes, const std::string& points,
                      const std::string& point_type, const std::string& connectivity,
                      const std::string& offsets, const std::string& index_type) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" " + file_attributes +
         ">\n<PolyData>\n<Piece NumberOfPoints=\"4\" NumberOfPolys=\"4\">\n<Points>\n"
         "<DataArray type=\"" + point_type + "\" NumberOfComponents=\"3\" format=\"binary\">\n" +
         points + "\n</DataArray>\n</Points>\n<Polys>\n<DataArray type=\"" + index_type +
         "\" Name=\"connectivity\" format=\"binary\">" + connectivity +
         "</DataArray>\n<DataArray type=\"" + index_type + "\" Name=\"offsets\" format=\"binary\">" +
         offsets + "</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
}

// pack('<I', 48) + pack('<12f', tetra); pack('<12i', faces); pack('<4i', 3, 6, 9, 12).
const char* kPoints32 = "MAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAAAAAACAPw==";
const char* kConnectivity32 = "MAAAAAAAAAACAAAAAQAAAAAAAAABAAAAAwAAAAEAAAACAAAAAwAAAAAAAAADAAAAAgAAAA==";
const char* kOffsets32 = "EAAAAAMAAAAGAAAACQAAAAwAAAA=";

TEST_F(MeshIoTest, VtpBinaryUInt32Header) {
  const TriMesh mesh = read_mesh(write_bytes(
      "t.vtp", vtp_tetra("byte_order=\"LittleEndian\"", kPoints32, "Float32", kConnectivity32,
                         kOffsets32, "Int32")));
  ASSERT_EQ(mesh.num_vertices(), 4u);
  EXPECT_EQ(mesh.vertices[1], Vec3(1, 0, 0));
  EXPECT_EQ(mesh.triangles[3], (Triangle{0, 3, 2}));
  EXPECT_NEAR(signed_volume(mesh), 1.0 / 6.0, 1e-15);
}

// VTK encodes the header and the data as two base64 runs: b64(pack('<I', 48)) + b64(data).
TEST_F(MeshIoTest, VtpBinaryHeaderEncodedSeparately) {
  const TriMesh mesh = read_mesh(write_bytes(
      "t.vtp", vtp_tetra("byte_order=\"LittleEndian\" header_type=\"UInt32\"",
                         "MAAAAA==AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/",
                         "Float32", kConnectivity32, kOffsets32, "Int32")));
  EXPECT_EQ(mesh.vertices[3], Vec3(0, 0, 1));
}

// pack('>Q', 96) + pack('>12d', ...), pack('>12q', ...), pack('>4q', ...): UInt64 header, big endian.
TEST_F(MeshIoTest, VtpBinaryBigEndianUInt64Header) {
  const TriMesh mesh = read_mesh(write_bytes(
      "t.vtp",
      vtp_tetra("byte_order=\"BigEndian\" header_type=\"UInt64\"",
                "AAAAAAAAAGAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA/8AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAD/"
                "wAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAP/AAAAAAAAA=",
                "Float64",
                "AAAAAAAAAGAAAAAAAAAAAAAAAAAAAAACAAAAAAAAAAEAAAAAAAAAAAAAAAAAAAABAAAAAAAAAAMAAAAAAAAAAQAA"
                "AAAAAAACAAAAAAAAAAMAAAAAAAAAAAAAAAAAAAADAAAAAAAAAAI=",
                "AAAAAAAAACAAAAAAAAAAAwAAAAAAAAAGAAAAAAAAAAkAAAAAAAAADA==", "Int64")));
  EXPECT_EQ(mesh.vertices[2], Vec3(0, 1, 0));
  EXPECT_NEAR(signed_volume(mesh), 1.0 / 6.0, 1e-15);
}

// ---- bad input: every case is one hipfai::Error "<path>: <problem>" ----

TEST_F(MeshIoTest, MissingFile) {
  const fs::path path = dir_ / "absent.stl";
  EXPECT_EQ(read_error(path), path.string() + ": no such file");
}

TEST_F(MeshIoTest, DirectoryIsNotAMesh) {
  fs::create_directories(dir_ / "folder.ply");
  EXPECT_NE(read_error(dir_ / "folder.ply").find("is a directory"), std::string::npos);
}

TEST_F(MeshIoTest, UnreadableFile) {
  const fs::path path = write_bytes("locked.obj", "v 0 0 0\n");
  fs::permissions(path, fs::perms::none);
  if (std::ifstream(path).good()) GTEST_SKIP() << "running with privileges that ignore permissions";
  EXPECT_NE(read_error(path).find("cannot open for reading"), std::string::npos);
}

TEST_F(MeshIoTest, UnknownExtension) {
  const fs::path path = write_bytes("mesh.off", "OFF\n");
  EXPECT_NE(read_error(path).find("unknown mesh format '.off'"), std::string::npos);
  EXPECT_THROW(write_mesh(make_box(Vec3::Zero(), Vec3::Ones(), 1), dir_ / "noext"), Error);
}

TEST_F(MeshIoTest, TruncatedBinaryStl) {
  std::string bytes(80, ' ');
  const std::uint32_t count = 3;
  bytes.append(reinterpret_cast<const char*>(&count), 4);  // little-endian host
  bytes.append(2 * 50 + 20, '\0');                          // 2.4 of 3 triangles
  EXPECT_NE(read_error(write_bytes("short.stl", bytes)).find("truncated binary STL: 2 of 3 triangles"),
            std::string::npos);
}

TEST_F(MeshIoTest, BinaryStlWithAbsurdCountIsRejectedWithoutAllocating) {
  std::string bytes(80, ' ');
  const std::uint32_t count = 4'000'000'000u;
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  bytes.append(1000, '\1');
  EXPECT_NE(read_error(write_bytes("huge.stl", bytes)).find("truncated binary STL"), std::string::npos);
}

TEST_F(MeshIoTest, TooShortToBeStl) {
  EXPECT_NE(read_error(write_bytes("tiny.stl", "hello")).find("not an STL file"), std::string::npos);
}

TEST_F(MeshIoTest, AsciiStlBadNumber) {
  const std::string text =
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 zero 0\nvertex 0 1 0\n"
      "endloop\nendfacet\nendsolid s\n";
  EXPECT_NE(read_error(write_bytes("bad.stl", text)).find("line 5: bad number 'zero'"), std::string::npos);
}

TEST_F(MeshIoTest, AsciiStlInfiniteCoordinate) {
  const std::string text =
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 inf\nvertex 0 1 0\n"
      "endloop\nendfacet\nendsolid s\n";
  EXPECT_NE(read_error(write_bytes("inf.stl", text)).find("non-finite coordinate"), std::string::npos);
}

TEST_F(MeshIoTest, ObjNanCoordinate) {
  EXPECT_NE(read_error(write_bytes("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"))
                .find("vertex 1 has a non-finite coordinate"),
            std::string::npos);
}

TEST_F(MeshIoTest, ObjIndexOutOfRange) {
  EXPECT_NE(read_error(write_bytes("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"))
                .find("refers to vertex 3 but the mesh has 3 vertices"),
            std::string::npos);
}

TEST_F(MeshIoTest, ObjNegativeIndexBeforeFirstVertex) {
  EXPECT_NE(read_error(write_bytes("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"))
                .find("line 4: relative face index -4"),
            std::string::npos);
}

TEST_F(MeshIoTest, ObjIndexZero) {
  EXPECT_NE(read_error(write_bytes("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"))
                .find("face index 0"),
            std::string::npos);
}

TEST_F(MeshIoTest, ObjHugeIndex) {
  EXPECT_NE(read_error(write_bytes("huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n"))
                .find("out of range"),
            std::string::npos);
}

TEST_F(MeshIoTest, EmptyMesh) {
  EXPECT_NE(read_error(write_bytes("empty.obj", "# nothing\n")).find("mesh has no vertices"),
            std::string::npos);
  EXPECT_NE(read_error(write_bytes("points.obj", "v 0 0 0\n")).find("mesh has no triangles"),
            std::string::npos);
  std::string stl(84, '\0');  // a valid binary STL with 0 triangles
  EXPECT_NE(read_error(write_bytes("empty.stl", stl)).find("mesh has no vertices"), std::string::npos);
}

const char* kPlyHead = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n";

TEST_F(MeshIoTest, PlyWithoutEndHeader) {
  EXPECT_NE(read_error(write_bytes("h.ply", kPlyHead)).find("PLY header has no end_header"),
            std::string::npos);
}

TEST_F(MeshIoTest, PlyUnknownPropertyType) {
  const std::string text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty real x\nend_header\n";
  EXPECT_NE(read_error(write_bytes("t.ply", text)).find("line 4: unknown property type 'real'"),
            std::string::npos);
}

TEST_F(MeshIoTest, PlyUnknownFormat) {
  const std::string text = "ply\nformat binary_middle_endian 1.0\nend_header\n";
  EXPECT_NE(read_error(write_bytes("f.ply", text)).find("unknown format 'binary_middle_endian'"),
            std::string::npos);
}

TEST_F(MeshIoTest, PlyNotPly) {
  EXPECT_NE(read_error(write_bytes("n.ply", "solid x\n")).find("not a PLY file"), std::string::npos);
}

TEST_F(MeshIoTest, PlyBadNumber) {
  const std::string text = std::string(kPlyHead) + "end_header\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n";
  EXPECT_NE(read_error(write_bytes("n.ply", text)).find("vertex 1: bad number 'x'"), std::string::npos);
}

TEST_F(MeshIoTest, PlyAsciiBodyEndsEarly) {
  const std::string text = std::string(kPlyHead) + "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n";
  EXPECT_NE(read_error(write_bytes("s.ply", text)).find("PLY body ends early in face 0 of 1"),
            std::string::npos);
}

TEST_F(MeshIoTest, PlyShortBinaryBody) {
  std::string text =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
      "property double y\nproperty double z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n";
  text.append(3 * 24, '\0');
  text.push_back(3);
  text.append(8, '\0');  // two of the three indices
  EXPECT_NE(read_error(write_bytes("s.ply", text)).find("PLY body ends early in face 0 of 1"),
            std::string::npos);
}

// A header declaring 4 billion faces over a 1 kB body must fail before allocating anything.
TEST_F(MeshIoTest, PlyAbsurdCount) {
  std::string text =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\nend_header\n";
  text.append(1024, '\0');
  EXPECT_NE(read_error(write_bytes("a.ply", text)).find("declares 4000000000 face elements"),
            std::string::npos);
}

TEST_F(MeshIoTest, PlyIndexOutOfRangeAndNegative) {
  const std::string head = std::string(kPlyHead) + "end_header\n0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_NE(read_error(write_bytes("r.ply", head + "3 0 1 3\n"))
                .find("face 0: vertex index 3 out of range (3 vertices)"),
            std::string::npos);
  EXPECT_NE(read_error(write_bytes("m.ply", head + "3 0 -1 2\n")).find("vertex index -1 out of range"),
            std::string::npos);
}

TEST_F(MeshIoTest, PlyWithoutFaces) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0 0 0\n";
  EXPECT_NE(read_error(write_bytes("p.ply", text)).find("mesh has no triangles"), std::string::npos);
}

TEST_F(MeshIoTest, VtpCompressedIsRejected) {
  const std::string text =
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "compressor=\"vtkZLibDataCompressor\"><PolyData></PolyData></VTKFile>";
  EXPECT_NE(read_error(write_bytes("z.vtp", text)).find("compressed VTP (vtkZLibDataCompressor) is not supported"),
            std::string::npos);
}

TEST_F(MeshIoTest, VtpAppendedIsRejected) {
  const std::string text =
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\"><PolyData>"
      "<Piece NumberOfPoints=\"3\" NumberOfPolys=\"1\"><Points><DataArray type=\"Float32\" "
      "NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/></Points></Piece></PolyData>"
      "<AppendedData encoding=\"raw\">_xxxx</AppendedData></VTKFile>";
  EXPECT_NE(read_error(write_bytes("a.vtp", text)).find("appended data"), std::string::npos);
}

TEST_F(MeshIoTest, VtpTruncatedBinaryArray) {
  // pack('<I', 48) + 24 of the 48 bytes.
  const std::string message = read_error(write_bytes(
      "t.vtp", vtp_tetra("byte_order=\"LittleEndian\"", "MAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAA==",
                         "Float32", kConnectivity32, kOffsets32, "Int32")));
  EXPECT_NE(message.find("truncated binary data (header says 48 bytes, 24 present)"), std::string::npos);
}

TEST_F(MeshIoTest, VtpWrongType) {
  const std::string text = "<VTKFile type=\"UnstructuredGrid\"></VTKFile>";
  EXPECT_NE(read_error(write_bytes("u.vtp", text)).find("not PolyData"), std::string::npos);
}

TEST_F(MeshIoTest, VtpConnectivityOutOfRange) {
  const std::string text =
      "<VTKFile type=\"PolyData\"><PolyData><Piece NumberOfPoints=\"3\" NumberOfPolys=\"1\">"
      "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\">0 0 0 1 0 0 0 1 0</DataArray></Points>"
      "<Polys><DataArray type=\"Int32\" Name=\"connectivity\">0 1 5</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\">3</DataArray></Polys></Piece></PolyData></VTKFile>";
  EXPECT_NE(read_error(write_bytes("c.vtp", text)).find("connectivity value 5 out of range"),
            std::string::npos);
}

// Prefixes and random single-byte corruptions of valid files of every format either read or
// throw hipfai::Error: never another exception and never a crash. (The sanitizer build runs this
// too, which turns an out-of-bounds read in a parser into a failure.)
TEST_F(MeshIoTest, TruncatedAndCorruptedFilesOnlyEverThrowError) {
  TriMesh mesh = make_box(Vec3(0.5, -1.0, 2.0), Vec3(1.5, 1.0, 3.25), 1);
  mesh.vertex_fields["t"] = std::vector<double>(mesh.num_vertices(), 0.125);
  std::mt19937 random(20090101);
  std::size_t errors = 0;
  std::size_t attempts = 0;
  for (const char* extension : {".stl", ".obj", ".ply", ".vtp"}) {
    for (const bool ascii : {false, true}) {
      const fs::path source = dir_ / (std::string("source") + extension);
      write_mesh(mesh, source, MeshWriteOptions{ascii});
      std::ifstream in(source, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      auto attempt = [&](const std::string& variant, const std::string& what) {
        // A fresh name each time: truncating and rewriting one file makes ext4 flush it to disk
        // on every close, which turned this millisecond test into a ten-second one under load.
        const fs::path path = write_bytes("variant" + std::to_string(++attempts) + extension, variant);
        try {
          read_mesh(path);
        } catch (const Error&) {
          ++errors;
        } catch (const std::exception& e) {
          ADD_FAILURE() << extension << (ascii ? " ascii " : " binary ") << what << ": " << e.what();
        }
        fs::remove(path);
      };
      const std::size_t stride = std::max<std::size_t>(1, bytes.size() / 120);
      for (std::size_t length = 0; length < bytes.size(); length += stride) {
        attempt(bytes.substr(0, length), "prefix of " + std::to_string(length) + " bytes");
      }
      for (int trial = 0; trial < 120; ++trial) {
        std::string variant = bytes;
        const std::size_t at = random() % variant.size();
        variant[at] = static_cast<char>(random() % 256);
        attempt(variant, "byte " + std::to_string(at) + " changed");
      }
    }
  }
  EXPECT_GT(errors, 500u);  // most variants are broken; the readers must have noticed
}

// ---- writing ----

TEST_F(MeshIoTest, FailedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path path = dir_ / "keep.ply";
  const TriMesh box = make_box(Vec3::Zero(), Vec3::Ones(), 1);
  write_mesh(box, path);
  const auto size_before = fs::file_size(path);
  TriMesh broken = box;
  broken.vertices[0].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_mesh(broken, path), Error);
  TriMesh badly_named = box;
  badly_named.vertex_fields["two words"] = std::vector<double>(box.num_vertices(), 1.0);
  EXPECT_THROW(write_mesh(badly_named, path), Error);
  EXPECT_EQ(fs::file_size(path), size_before);
  EXPECT_EQ(read_mesh(path).vertices, box.vertices);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(MeshIoTest, WriteIntoMissingFolderFails) {
  const fs::path path = dir_ / "no" / "such" / "folder.stl";
  try {
    write_mesh(make_box(Vec3::Zero(), Vec3::Ones(), 1), path);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": cannot write", 0), 0u) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace hipfai::geometry
