// Mesh files (OBJ, ASCII and binary STL), shapes loaded from them, and the error messages of the
// readers and of the built-in specs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <sys/stat.h>
#include <unistd.h>

#include "solver/shape/builtins.hpp"
#include "solver/shape/mesh_io.hpp"

namespace talus {
namespace {

std::string temp_path(const std::string& name) {
  return testing::TempDir() + "talus_shape_" + std::to_string(::getpid()) + "_" + name;
}

std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The message of the exception `call` throws, or a marker that it threw none.
template <class Exception, class Call>
std::string error_of(Call call) {
  try {
    call();
  } catch (const Exception& e) {
    return e.what();
  }
  return "<no exception>";
}

#define EXPECT_HAS(text, part)                               \
  EXPECT_NE(std::string(text).find(part), std::string::npos) \
      << "'" << (text) << "' lacks '" << (part) << "'"

void expect_same_shape(const ShapeTemplate& a, const ShapeTemplate& b, double rel) {
  EXPECT_EQ(a.vertices.size(), b.vertices.size());
  EXPECT_EQ(a.faces.size(), b.faces.size());
  EXPECT_NEAR(a.volume, b.volume, rel * b.volume);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(a.principal_moments[k], b.principal_moments[k], rel * b.principal_moments[k]);
  EXPECT_NEAR(a.bounding_radius, b.bounding_radius, rel * b.bounding_radius);
}

TEST(MeshFiles, CylinderRoundTripsThroughObjAndAsciiStlExactly) {
  const TriangleMesh mesh = cylinder_mesh(8e-3, 5.3e-3, 20);
  const ShapeTemplate expected = make_builtin("cylinder:0.008,0.0053,20");
  const std::string obj = temp_path("cylinder.obj"), stl = temp_path("cylinder.stl");
  write_obj(obj, mesh);
  write_stl(stl, mesh, false);
  for (const std::string& path : {obj, stl}) {
    SCOPED_TRACE(path);
    const TriangleMesh read = read_mesh(path);
    EXPECT_EQ(read.vertices.size(), 42u);  // STL corners merged back to 42
    EXPECT_EQ(read.triangles.size(), 80u);
    for (std::size_t v = 0; v < read.vertices.size() && path == obj; ++v)
      EXPECT_EQ(norm(read.vertices[v] - mesh.vertices[v]), 0.0);  // %.17g is exact
    testing::internal::CaptureStderr();
    const ShapeTemplate shape = load_shape_file(path);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");  // convex: no warning
    expect_same_shape(shape, expected, 1e-14);  // same points, possibly another triangulation
    EXPECT_EQ(shape.faces.size(), 22u);
  }
}

TEST(MeshFiles, BinaryStlRoundTripsToFloatPrecision) {
  const std::string path = temp_path("mineral.stl");
  const ShapeTemplate mineral = make_builtin("mineral:20");  // millimetres
  write_stl(path, {mineral.vertices, mineral.triangles}, true);
  const TriangleMesh read = read_stl(path);
  EXPECT_EQ(read.vertices.size(), 18u);
  EXPECT_EQ(read.triangles.size(), 32u);
  const ShapeTemplate shape = load_shape_file(path, 1e-3);  // to metres
  // Coordinates rounded to float: relative 6e-8 each, a few of them per moment.
  expect_same_shape(shape, make_builtin("mineral:0.02"), 1e-6);
  EXPECT_EQ(shape.faces.size(), 32u);
  // make_shape: "path:scale" and plain path.
  expect_same_shape(make_shape(path + ":0.001"), shape, 1e-15);
  expect_same_shape(make_shape(path), make_builtin("mineral:20"), 1e-6);
}

TEST(MeshFiles, ObjQuadsSlashedIndicesNegativeIndicesAndCommentsAreRead) {
  const std::string path = write_text("cube.obj",
                                      "# a unit cube with quads\r\n"
                                      "mtllib cube.mtl\no cube\n"
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                      "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1   # top\n"
                                      "vn 0 0 1\nvt 0 0\ns off\nusemtl stone\n"
                                      "f 1 4 3 2\nf 5/1 6/1 7/1 8/1\nf 1//1 2//1 6//1 5//1\n"
                                      "f -7 -6 -2 -3\nf 3 4 8 7\nf 4 1 5 8\n");
  const TriangleMesh mesh = read_obj(path);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);  // six quads, fanned
  // "f -7 -6 -2 -3" after 8 vertices is "f 2 3 7 6": its first triangle holds indices 1, 2, 6.
  EXPECT_EQ(mesh.triangles[6], (std::array<int, 3>{1, 2, 6}));
  testing::internal::CaptureStderr();
  const ShapeTemplate shape = load_shape_file(path, 0.5);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_NEAR(shape.volume, 0.125, 1e-15);
  EXPECT_EQ(shape.faces.size(), 6u);
}

TEST(MeshFiles, NonConvexMeshWarnsOnceAndUsesItsHull) {
  // A cube [-1, 1]^3 whose top face is replaced by four triangles to a dimple at (0, 0, 0.3).
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
  mesh.vertices.push_back({0, 0, 0.3});
  mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {0, 1, 5}, {0, 5, 4}, {1, 3, 7}, {1, 7, 5}, {3, 2, 6},
                    {3, 6, 7}, {2, 0, 4}, {2, 4, 6}, {4, 5, 8}, {5, 7, 8}, {7, 6, 8}, {6, 4, 8}};
  const std::string obj = temp_path("dimpled.obj"), stl = temp_path("dimpled.stl");
  write_obj(obj, mesh);
  write_stl(stl, mesh, true);
  for (const std::string& path : {obj, stl}) {
    testing::internal::CaptureStderr();
    const ShapeTemplate shape = load_shape_file(path);
    EXPECT_EQ(testing::internal::GetCapturedStderr(),
              path + ": mesh is not convex; using its convex hull\n");
    EXPECT_EQ(shape.vertices.size(), 8u);  // the dimple is dropped
    EXPECT_EQ(shape.faces.size(), 6u);
    EXPECT_NEAR(shape.volume, 8.0, 1e-14);
    EXPECT_NEAR(shape.bounding_radius, std::sqrt(3.0), 1e-14);
  }
  // A mesh that is convex but whose faces are inward-oriented is not reported.
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  mesh.vertices[8] = {0, 0, 1};
  mesh.triangles.resize(10);
  mesh.triangles.push_back({4, 7, 5});
  mesh.triangles.push_back({4, 6, 7});
  write_obj(obj, mesh);
  testing::internal::CaptureStderr();
  load_shape_file(obj);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  // Every vertex on the hull, but one triangle cuts through the body: its centroid
  // (-1/3, 1/3, -1/3) lies 2/3 inside the nearest face, so the mesh is reported.
  mesh.triangles.push_back({0, 3, 6});
  write_obj(obj, mesh);
  testing::internal::CaptureStderr();
  load_shape_file(obj);
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            obj + ": mesh is not convex; using its convex hull\n");
}

TEST(MeshFiles, ObjErrorsNameFileLineAndExpectation) {
  const auto obj_error = [](const std::string& name, const std::string& text) {
    const std::string path = write_text(name, text);
    return std::make_pair(path, error_of<std::runtime_error>([&] { read_obj(path); }));
  };
  {
    const auto [path, message] = obj_error("short_vertex.obj", "v 0 0 0\n\nv 1 2\n");
    EXPECT_HAS(message, path + ":3: expected 'v x y z' with three numbers");
  }
  {
    const auto [path, message] = obj_error("word_vertex.obj", "v 0 zero 0\n");
    EXPECT_HAS(message, path + ":1: vertex y 'zero' is not a number; expected 'v x y z'");
  }
  {
    const auto [path, message] = obj_error("short_face.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
    EXPECT_HAS(message, path + ":3: expected 'f a b c' with at least three vertex indices");
  }
  {
    const auto [path, message] = obj_error("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n");
    EXPECT_HAS(message, path + ":4: expected a vertex index");
  }
  {
    const auto [path, message] =
        obj_error("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\nv 0 0 1\n");
    EXPECT_HAS(message, path + ":4: face refers to vertex 9, but the file has 4 vertices");
  }
  {
    const auto [path, message] = obj_error("negative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
    EXPECT_HAS(message, path + ":3: face vertex -3 refers before the first vertex");
  }
  {
    const auto [path, message] = obj_error("unknown.obj", "v 0 0 0\nvx 1 2 3\n");
    EXPECT_HAS(message, path + ":2: unknown statement 'vx'; expected 'v' or 'f'");
  }
  {
    const auto [path, message] = obj_error("empty.obj", "# nothing\n");
    EXPECT_HAS(message, path + ": no vertices; expected 'v x y z' lines");
  }
  const std::string missing = temp_path("missing.obj");
  EXPECT_HAS(error_of<std::runtime_error>([&] { read_obj(missing); }),
             missing + ": does not exist");
}

TEST(MeshFiles, StlErrorsNameFileLineAndExpectation) {
  const std::string facet =
      "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n"
      " endloop\nendfacet\n";
  const auto stl_error = [](const std::string& name, const std::string& text) {
    const std::string path = write_text(name, text);
    return std::make_pair(path, error_of<std::runtime_error>([&] { read_stl(path); }));
  };
  {
    const auto [path, message] =
        stl_error("loop.stl", "solid x\n" + facet + "facet normal 0 0 1\n outer lop\n");
    EXPECT_HAS(message, path + ":10: expected 'outer loop', got 'lop'");
  }
  {
    const auto [path, message] = stl_error(
        "number.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 zero 0\n");
    EXPECT_HAS(message, path + ":5: 'zero' is not a number; expected 'vertex x y z'");
  }
  {
    const auto [path, message] = stl_error("eof.stl", "solid x\n" + facet);
    EXPECT_HAS(message, path +
                            ":9: unexpected end of file; expected 'facet normal nx ny nz' or "
                            "'endsolid'");
  }
  {
    const auto [path, message] = stl_error("keyword.stl", "solid x\n" + facet + "face\n");
    EXPECT_HAS(message, path + ":9: expected 'facet normal nx ny nz' or 'endsolid', got 'face'");
  }
  {
    const auto [path, message] = stl_error("nofacets.stl", "solid x\nendsolid x\n");
    EXPECT_HAS(message, path + ": ASCII STL has no facets");
  }
  {
    const auto [path, message] = stl_error("garbage.stl", "hello");
    EXPECT_HAS(message, path + ": expected an ASCII STL starting with 'solid' or a binary STL");
  }
  {
    // A binary header announcing 3 triangles, with only one stored.
    std::string data(80, ' ');
    const std::uint32_t count = 3;
    data.append(reinterpret_cast<const char*>(&count), 4);
    data.append(50, '\0');
    const auto [path, message] = stl_error("truncated.stl", data);
    EXPECT_HAS(message, path +
                            ": binary STL header announces 3 triangles (234 bytes), but the "
                            "file has 134 bytes");
  }
  {
    // A well-formed binary file with no facets (header count 0, 84 bytes).
    std::string data(84, '\0');
    const auto [path, message] = stl_error("empty_binary.stl", data);
    EXPECT_HAS(message, path + ": binary STL has no facets");
  }
  const std::string missing = temp_path("missing.stl");
  EXPECT_HAS(error_of<std::runtime_error>([&] { read_stl(missing); }),
             missing + ": does not exist");
  const std::string other = write_text("shape.ply", "ply\n");
  EXPECT_HAS(error_of<std::runtime_error>([&] { read_mesh(other); }),
             other + ": unknown mesh file type; expected an .obj or .stl file");
}

TEST(MeshFiles, BinaryStlWithANonFiniteVertexIsRefusedLikeTheTextFormats) {
  // A tetrahedron; then one coordinate of one corner overwritten in the stored floats. Record t
  // starts at byte 84 + 50 t; its corner c coordinate k at 12 (normal) + 12 c + 4 k after that.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const std::string good = temp_path("tetra.stl");
  write_stl(good, mesh, true);
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 84u + 4 * 50);
  ASSERT_EQ(read_stl(good).vertices.size(), 4u);  // the untouched file reads
  const auto with_value = [&](const std::string& name, float value) {
    std::string data = bytes;
    std::memcpy(&data[84 + 2 * 50 + 12 + 12 * 2 + 4 * 2], &value, 4);  // triangle 2, corner 3, z
    return write_text(name, data);
  };
  const std::string nan = with_value("nan.stl", std::nanf(""));
  EXPECT_EQ(error_of<std::runtime_error>([&] { read_stl(nan); }),
            nan +
                ": binary STL triangle 2 (record at byte 184): vertex 3 z is NaN; expected a "
                "finite number");
  const std::string inf = with_value("inf.stl", -INFINITY);
  EXPECT_EQ(error_of<std::runtime_error>([&] { load_shape_file(inf); }),
            inf +
                ": binary STL triangle 2 (record at byte 184): vertex 3 z is infinite; "
                "expected a finite number");
  // The ASCII reader refuses the same value the same way (line and expectation).
  const std::string ascii = write_text(
      "nan_ascii.stl",
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 nan\n"
      "endloop\nendfacet\nendsolid t\n");
  EXPECT_HAS(error_of<std::runtime_error>([&] { read_stl(ascii); }),
             ascii + ":6: 'nan' is not a finite number; expected 'vertex x y z'");
}

TEST(MeshFiles, DirectoriesFifosAndDevicesAreRefusedAsWhatTheyAre) {
  const std::string directory = temp_path("folder.stl");
  std::filesystem::create_directory(directory);
  EXPECT_EQ(error_of<std::runtime_error>([&] { read_stl(directory); }),
            directory + ": is a directory, not a regular file");
  // A FIFO with no writer: opening it for reading would block forever.
  const std::string fifo = temp_path("pipe.obj");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(error_of<std::runtime_error>([&] { load_shape_file(fifo); }),
            fifo + ": is a FIFO (named pipe), not a regular file");
  // /dev/zero never ends: read, it would fill memory.
  EXPECT_EQ(error_of<std::runtime_error>([&] { read_stl("/dev/zero"); }),
            "/dev/zero: is a character device, not a regular file");
  EXPECT_EQ(error_of<std::runtime_error>([&] { read_obj("/dev/null"); }),
            "/dev/null: is a character device, not a regular file");
  std::filesystem::remove(directory);
  std::filesystem::remove(fifo);
}

TEST(MeshFiles, ShapeLoadingErrorsNameTheFile) {
  const std::string flat = write_text("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n");
  const std::string message = error_of<std::runtime_error>([&] { load_shape_file(flat); });
  EXPECT_HAS(message, flat + ": cannot build a convex shape from the mesh");
  EXPECT_HAS(message, "coplanar");
  EXPECT_HAS(error_of<std::invalid_argument>([&] { load_shape_file(flat, -1); }),
             flat + ": scale must be a positive finite number");
  EXPECT_HAS(error_of<std::invalid_argument>([&] { make_shape("grain.stl:big"); }),
             "shape spec 'grain.stl:big': expected 'path:scale' with a positive scale factor");
}

TEST(MeshFiles, BadBytesAndLongLinesAreNotEchoedRaw) {
  const auto obj_error = [](const std::string& name, const std::string& text) {
    const std::string path = write_text(name, text);
    return std::make_pair(path, error_of<std::runtime_error>([&] { read_obj(path); }));
  };
  {
    const auto [path, message] = obj_error("nul.obj", std::string("v 0 0 0\nv 1 0 0\0\n", 17));
    EXPECT_EQ(message, path +
                           ":2: vertex z '0\\x00' is not a number; expected 'v x y z' with "
                           "three numbers");
  }
  {
    const auto [path, message] = obj_error("latin1.obj", "v 0 0 \xE9\xFF\n");
    EXPECT_HAS(message, path + ":1: vertex z '\\xE9\\xFF' is not a number");
  }
  {
    const auto [path, message] = obj_error("long.obj", "v 0 0 " + std::string(5000, '7') + "x\n");
    EXPECT_HAS(message, "... (5001 bytes)' is not a number");
    EXPECT_LT(message.size(), 300u);
  }
  {
    const auto [path, message] = obj_error("nan.obj", "v 0 0 0\nv 1 inf 0\n");
    EXPECT_HAS(message, path + ":2: vertex y 'inf' is not a finite number");
  }
  {
    const auto [path, message] =
        obj_error("overflow.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n");
    EXPECT_HAS(message, path +
                            ":4: face vertex index '99999999999999999999999' is beyond the "
                            "vertices any file can hold");
  }
}

TEST(MeshFiles, ShapesFromFilesStayWithinTheSizeRange) {
  const std::string tetra = write_text("unit_tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n");
  EXPECT_EQ(error_of<std::runtime_error>([&] { load_shape_file(tetra, 1e300); }),
            tetra +
                ": a vertex lies 1e+300 m from the origin (scaled by 1e+300), beyond the "
                "largest size talus supports, 1e+06 m");
  EXPECT_EQ(error_of<std::runtime_error>([&] { load_shape_file(tetra, 1e-10); }),
            tetra +
                ": the mesh is 1e-10 m across (scaled by 1e-10), below the smallest size "
                "talus supports, 1e-07 m");
  const std::string far = write_text("far.obj", "v 2e6 0 0\nv 2e6 1 0\nv 2e6 0 1\nv 2e6 1 1\n");
  EXPECT_HAS(error_of<std::runtime_error>([&] { load_shape_file(far); }),
             far + ": a vertex lies 2e+06 m from the origin, beyond the largest size");
}

TEST(Builtins, BadSpecsNameTheSpecAndWhatWasExpected) {
  const auto spec_error = [](const std::string& spec) {
    return error_of<std::invalid_argument>([&] { make_builtin(spec); });
  };
  EXPECT_HAS(spec_error("blob:1"),
             "shape spec 'blob:1': unknown shape 'blob'; expected one of "
             "tetrahedron, cube, octahedron, dodecahedron, icosahedron, "
             "cuboid, cylinder, corn, mineral");
  EXPECT_HAS(spec_error("cube"),
             "shape spec 'cube': cube needs one positive size D, the "
             "circumscribed-sphere diameter in metres");
  EXPECT_HAS(spec_error("cube:-1"), "shape spec 'cube:-1': cube needs one positive size D");
  EXPECT_HAS(spec_error("icosahedron:1cm"), "shape spec 'icosahedron:1cm': icosahedron needs");
  EXPECT_HAS(spec_error("mineral:1,2"),
             "shape spec 'mineral:1,2': mineral needs one positive size");
  EXPECT_HAS(spec_error("cuboid:1,2"),
             "shape spec 'cuboid:1,2': cuboid needs three positive side "
             "lengths a,b,c");
  EXPECT_HAS(spec_error("cuboid:1,0,2"), "cuboid needs three positive side lengths");
  EXPECT_HAS(spec_error("cylinder:1"), "shape spec 'cylinder:1': cylinder needs 'D,L' or 'D,L,N'");
  EXPECT_HAS(spec_error("cylinder:1,2,2.5"),
             "shape spec 'cylinder:1,2,2.5': N = 2.5: expected an integer number of sides from 3 "
             "to 100000");
  EXPECT_HAS(spec_error("cylinder:1,2,2"), "N = 2: expected an integer number of sides");
  EXPECT_HAS(spec_error("cylinder:1,2,100001"), "N = 100001: expected an integer number of sides");
  // Sizes beyond the range talus supports are called that, not what the hull makes of them.
  EXPECT_HAS(spec_error("cube:1e300"),
             "shape spec 'cube:1e300': size D 1e+300 m is beyond the largest size talus supports, "
             "1e+06 m");
  EXPECT_HAS(spec_error("cuboid:1e200,1,1"), "side a 1e+200 m is beyond the largest size");
  EXPECT_HAS(spec_error("cylinder:0.01,1e-12"),
             "length L 1e-12 m is below the smallest size talus supports, 1e-07 m");
  EXPECT_HAS(spec_error("cube:nan"), "cube needs one positive size D");
  EXPECT_HAS(spec_error("cube:nan"), ", got 'nan'");
  EXPECT_HAS(spec_error("grain.ply"),
             "shape spec 'grain.ply': 'grain.ply' is not a mesh file talus reads");
  // make_shape passes a non-file spec on to make_builtin.
  EXPECT_HAS(error_of<std::invalid_argument>([] { make_shape("sphere:1"); }),
             "a sphere is not a polyhedron shape");
  EXPECT_EQ(builtin_names().size(), 9u);
  for (const std::string& name : builtin_names()) {
    const std::string spec = name == "cuboid"     ? "cuboid:1,2,3"
                             : name == "cylinder" ? "cylinder:1,1"
                                                  : name + ":1";
    EXPECT_GT(make_shape(spec).volume, 0) << spec;
  }
}

}  // namespace
}  // namespace talus
