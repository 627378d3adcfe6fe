// ParaView output: the XML pieces (base64, the PolyData layout, the .pvd collection), the
// particles as posed surfaces and as points, the walls where their motion has taken them, the
// default particle form, and the series on disk: files per frame, walls written again only when
// they changed, collections that always list complete frames. tests/io/vtk_readback.py reads a
// real run's files with VTK itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <regex>
#include <stdexcept>

#include "solver/io/vtk_output.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using talus_test::file_names;
using talus_test::read_text;

std::string test_directory(const std::string& name) {
  return talus_test::fresh_test_directory("test-io-vtk", name);
}

// A dodecahedron and a ball, and the walls given.
Scene scene_with(const std::string& walls, const std::string& vtk = "{every: 1}") {
  const std::string text = R"(time: {step: 1.0e-3, end: 1.0}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  grain: {shape: dodecahedron:0.01, material: glass}
  ball: {sphere: 0.004, material: glass}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0.05]}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 0.0}
)" + walls +
                           "outputs:\n  vtk: " + vtk + "\n";
  return parse_scene(text, "vtk.yaml", ".");
}

TrajectoryRow row(long long id, int template_index, const Vec3d& position,
                  const Quatd& orientation = Quatd()) {
  TrajectoryRow r;
  r.id = id;
  r.template_index = template_index;
  r.position = position;
  r.orientation = orientation;
  r.velocity = {0.25 * double(id + 1), -1.0 / 3, 9.81};
  r.angular_velocity = {1.5, 0, -2.0 / 7};
  return r;
}

// RFC 4648 base64 back to bytes (the test's own decoder; padding ends the data).
std::string decoded(const std::string& text) {
  const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  unsigned bits = 0;
  int held = 0;
  for (const char c : text) {
    if (c == '=') break;
    bits = bits << 6 | unsigned(digits.find(c));
    held += 6;
    if (held >= 8) {
      held -= 8;
      bytes += char((bits >> held) & 0xff);
    }
  }
  return bytes;
}

// The bytes of the DataArray named `name` in a .vtp text, after its UInt64 byte count (checked).
std::string array_bytes(const std::string& vtp, const std::string& name) {
  const std::regex pattern("Name=\"" + name + "\"[^>]*format=\"binary\">([^<]*)<");
  std::smatch match;
  if (!std::regex_search(vtp, match, pattern)) {
    ADD_FAILURE() << "no array " << name;
    return "";
  }
  const std::string bytes = decoded(match[1].str());
  std::uint64_t size = 0;
  std::memcpy(&size, bytes.data(), sizeof size);
  EXPECT_EQ(size, bytes.size() - sizeof size) << name;
  return bytes.substr(sizeof size);
}

template <class T>
std::vector<T> values_of(const std::string& bytes) {
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

std::vector<double> doubles(const VtkArray& array) {
  return values_of<double>(array.bytes());
}

TEST(VtkXml, Base64MatchesRfc4648) {
  // The test vectors of RFC 4648 §10: every padding case.
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\xfe\x00", 3)), "//4A");  // high bits, a zero byte
}

TEST(VtkXml, PolyDataPieceCountsAndBinaryArrays) {
  VtkPolyData data;
  for (const double x : {0.1, 1.0 / 3, -0.0, 1e-310, 2.0, 3.0, 4.0, 5.0, 6.0}) data.points.add(x);
  data.vertex_cells = {2};
  data.add_polygon({0, 1, 2});
  VtkArray id("id", VtkArray::Type::int64);
  id.add(std::int64_t(7));
  id.add(std::int64_t(-1));
  VtkArray speed("speed", VtkArray::Type::float64);
  for (const double s : {0.5, 1.5, 2.5}) speed.add(s);
  data.cell_data = {id};
  data.point_data = {speed};
  const std::string vtp = vtp_text(data);
  EXPECT_NE(vtp.find("<Piece NumberOfPoints=\"3\" NumberOfVerts=\"1\" NumberOfLines=\"0\" "
                     "NumberOfStrips=\"0\" NumberOfPolys=\"1\">"),
            std::string::npos)
      << vtp;
  // The bits as written, -0 and a subnormal included.
  const std::string points = array_bytes(vtp, "Points");
  ASSERT_EQ(points.size(), 9 * sizeof(double));
  EXPECT_EQ(std::memcmp(points.data(), data.points.bytes().data(), points.size()), 0);
  EXPECT_EQ(values_of<std::int64_t>(array_bytes(vtp, "id")), (std::vector<std::int64_t>{7, -1}));
  EXPECT_EQ(values_of<double>(array_bytes(vtp, "speed")), (std::vector<double>{0.5, 1.5, 2.5}));
  // Cells: Verts first, then Polys, each with its connectivity and the end of each cell.
  const std::size_t verts = vtp.find("<Verts>"), polys = vtp.find("<Polys>");
  ASSERT_NE(verts, std::string::npos);
  ASSERT_NE(polys, std::string::npos);
  EXPECT_LT(verts, polys);
  EXPECT_EQ(values_of<std::int64_t>(array_bytes(vtp.substr(verts, polys - verts), "offsets")),
            std::vector<std::int64_t>{1});
  EXPECT_EQ(values_of<std::int64_t>(array_bytes(vtp.substr(polys), "connectivity")),
            (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(values_of<std::int64_t>(array_bytes(vtp.substr(polys), "offsets")),
            std::vector<std::int64_t>{3});
}

TEST(VtkXml, AnArrayThatDoesNotFitIsABug) {
  VtkPolyData data;
  for (int k = 0; k < 3; ++k) data.points.add(0.0);
  VtkArray velocity("velocity", VtkArray::Type::float64, 3);
  velocity.add(1.0);  // one value of a point's three
  data.point_data = {velocity};
  EXPECT_THROW(vtp_text(data), std::logic_error);
  EXPECT_THROW(velocity.add(std::int64_t(1)), std::logic_error);  // not the array's type
}

TEST(VtkXml, PvdListsEveryEntryWithItsExactTime) {
  EXPECT_EQ(pvd_text({{0, "a_0.vtp"}, {0.1, "a_1.vtp"}}),
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
            "  <Collection>\n"
            "    <DataSet timestep=\"0\" part=\"0\" file=\"a_0.vtp\"/>\n"
            "    <DataSet timestep=\"0.10000000000000001\" part=\"0\" file=\"a_1.vtp\"/>\n"
            "  </Collection>\n"
            "</VTKFile>\n");
}

TEST(VtkOutput, DefaultParticleFormFollowsTheRunsSize) {
  const Scene plain = scene_with("");
  EXPECT_EQ(vtk_particles_for(plain, kVtkSurfaceParticleLimit), VtkParticles::surfaces);
  EXPECT_EQ(vtk_particles_for(plain, kVtkSurfaceParticleLimit + 1), VtkParticles::points);
  // A feed's particles count: 10 per second for 1 s is 10 more.
  Scene fed = plain;
  FeedRequest feed;
  feed.rate = 10;
  feed.start = 0;
  feed.stop = 1;
  fed.feeds.push_back(feed);
  EXPECT_EQ(vtk_particles_for(fed, kVtkSurfaceParticleLimit - 10), VtkParticles::surfaces);
  EXPECT_EQ(vtk_particles_for(fed, kVtkSurfaceParticleLimit - 9), VtkParticles::points);
  // The scene's choice wins either way.
  EXPECT_EQ(vtk_particles_for(scene_with("", "{every: 1, particles: points}"), 1),
            VtkParticles::points);
  EXPECT_EQ(vtk_particles_for(scene_with("", "{every: 1, particles: surfaces}"), 1000000),
            VtkParticles::surfaces);
}

TEST(VtkOutput, SphereSurfaceIsClosedOutwardAndOnTheSphere) {
  const Scene scene = scene_with("");
  const TemplateSurface s = template_surface(scene.templates[1]);
  const double r = 0.004;
  // Two poles and kSphereBands - 1 rings; two fans and kSphereBands - 2 bands of quadrilaterals.
  EXPECT_EQ(s.vertices.size(), std::size_t(2 + (kSphereBands - 1) * kSphereSegments));
  EXPECT_EQ(s.faces.size(), std::size_t(kSphereBands * kSphereSegments));
  for (const Vec3d& v : s.vertices) EXPECT_NEAR(norm(v), r, 4 * r * 1e-16);  // sin, cos rounding
  std::map<std::pair<int, int>, int> edges;  // directed edge -> times used
  for (const std::vector<int>& face : s.faces) {
    const Vec3d a = s.vertices[face[0]], b = s.vertices[face[1]], c = s.vertices[face[2]];
    EXPECT_GT(dot(cross(b - a, c - a), a + b + c), 0);  // counter-clockwise from outside
    for (std::size_t k = 0; k < face.size(); ++k) ++edges[{face[k], face[(k + 1) % face.size()]}];
  }
  // Closed: every edge used once each way.
  for (const auto& [edge, uses] : edges) {
    EXPECT_EQ(uses, 1);
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
  }
}

TEST(VtkOutput, SurfacesAreTheTemplatesFacesPosed) {
  const Scene scene = scene_with("");
  const std::vector<TemplateSurface> surfaces = {template_surface(scene.templates[0]),
                                                 template_surface(scene.templates[1])};
  const ShapeTemplate& grain = scene.templates[0].shape;
  // A quarter turn about z: (x, y, z) -> (-y, x, z).
  const double h = std::sqrt(0.5);
  const std::vector<TrajectoryRow> rows = {row(4, 1, {1, 2, 3}),
                                           row(9, 0, {0.5, -0.25, 2}, Quatd(h, 0, 0, h))};
  const VtkPolyData data = particle_surfaces(surfaces, rows);
  const std::size_t ball_points = surfaces[1].vertices.size();
  ASSERT_EQ(data.point_count(), ball_points + grain.vertices.size());
  ASSERT_EQ(data.polygon_ends.size(), surfaces[1].faces.size() + grain.faces.size());
  const std::vector<double> points = doubles(data.points);
  for (std::size_t k = 0; k < grain.vertices.size(); ++k) {
    const Vec3d v = grain.vertices[k];
    const Vec3d expected = Vec3d(0.5, -0.25, 2) + Vec3d(-v.y, v.x, v.z);
    for (int c = 0; c < 3; ++c)  // h is sqrt(1/2) rounded: a few units of 1e-16 of the scale 2
      EXPECT_NEAR(points[3 * (ball_points + k) + c], expected[c], 1e-15) << k;
  }
  // The grain's first face: its template loop shifted past the ball's points.
  const std::size_t first = surfaces[1].faces.size();
  const std::vector<int>& loop = grain.faces[0].loop;
  ASSERT_EQ(data.polygon_ends[first] - data.polygon_ends[first - 1], std::int64_t(loop.size()));
  for (std::size_t k = 0; k < loop.size(); ++k)
    EXPECT_EQ(data.polygon_points[data.polygon_ends[first - 1] + k],
              std::int64_t(ball_points) + loop[k]);
  // Cell data, one entry per face, the row's values.
  ASSERT_EQ(data.cell_data.size(), 4u);
  EXPECT_EQ(data.cell_data[0].name(), "id");
  const std::vector<std::int64_t> ids = values_of<std::int64_t>(data.cell_data[0].bytes());
  EXPECT_EQ(ids[first - 1], 4);
  EXPECT_EQ(ids[first], 9);
  EXPECT_EQ(values_of<std::int32_t>(data.cell_data[1].bytes())[first], 0);
  const std::vector<double> velocity = doubles(data.cell_data[2]);
  EXPECT_EQ(velocity[3 * first], rows[1].velocity.x);
  EXPECT_EQ(velocity[3 * first + 1], -1.0 / 3);
  EXPECT_EQ(doubles(data.cell_data[3])[3 * first + 2], -2.0 / 7);
}

TEST(VtkOutput, PointsCarryEachRowsState) {
  const Scene scene = scene_with("");
  const std::vector<TrajectoryRow> rows = {row(4, 1, {1, 2, 3}),
                                           row(9, 0, {0.5, -0.25, 2}, Quatd(0.5, 0.5, -0.5, 0.5))};
  const VtkPolyData data = particle_points(scene, rows);
  EXPECT_EQ(doubles(data.points), (std::vector<double>{1, 2, 3, 0.5, -0.25, 2}));
  EXPECT_EQ(data.vertex_cells, (std::vector<std::int64_t>{0, 1}));
  EXPECT_TRUE(data.polygon_ends.empty());
  std::map<std::string, const VtkArray*> arrays;
  for (const VtkArray& a : data.point_data) arrays[a.name()] = &a;
  ASSERT_EQ(arrays.size(), 6u);
  EXPECT_EQ(values_of<std::int64_t>(arrays["id"]->bytes()), (std::vector<std::int64_t>{4, 9}));
  EXPECT_EQ(values_of<std::int32_t>(arrays["template"]->bytes()),
            (std::vector<std::int32_t>{1, 0}));
  EXPECT_EQ(arrays["orientation"]->components(), 4);
  EXPECT_EQ(doubles(*arrays["orientation"]),
            (std::vector<double>{1, 0, 0, 0, 0.5, 0.5, -0.5, 0.5}));
  EXPECT_EQ(doubles(*arrays["velocity"])[3], 2.5);  // (id + 1) / 4 for id 9
  EXPECT_EQ(doubles(*arrays["angular_velocity"])[5], -2.0 / 7);
  EXPECT_EQ(doubles(*arrays["bounding_radius"]),
            (std::vector<double>{0.004, scene.templates[0].bounding_radius}));
}

TEST(VtkOutput, WallsFollowTheirMotionAndDropAnOpenedPlate) {
  const Scene scene = scene_with(R"(walls:
  - hopper: {base: [0, 0, 0], bottom_radius: 0.01, top_radius: 0.05, height: 0.05,
             outlet: closed, outlet_opens_at: 0.25, segments: 8, material: glass,
             motion: {translation: {velocity: [0.5, 0, -1]}}}
)");
  const std::vector<WallMesh> meshes = make_wall_meshes(scene);
  const std::size_t all = meshes[0].mesh.triangles.size();
  const std::size_t plate = std::size_t(meshes[0].plate_triangles);
  ASSERT_GT(plate, 0u);
  const VtkPolyData closed = wall_polygons(scene, meshes, 0.1);
  EXPECT_EQ(closed.polygon_ends.size(), all);
  const VtkPolyData open = wall_polygons(scene, meshes, 0.3);
  EXPECT_EQ(open.polygon_ends.size(), all - plate);
  EXPECT_EQ(values_of<std::int32_t>(open.cell_data[0].bytes()),
            std::vector<std::int32_t>(all - plate, 0));
  // Every point moved by velocity * t from where the mesh is at t = 0.
  const std::vector<double> points = doubles(open.points);
  ASSERT_EQ(points.size(), 3 * meshes[0].mesh.vertices.size());
  for (std::size_t k = 0; k < meshes[0].mesh.vertices.size(); ++k) {
    const Vec3d v = meshes[0].mesh.vertices[k];
    EXPECT_NEAR(points[3 * k], v.x + 0.15, 1e-16);
    EXPECT_EQ(points[3 * k + 1], v.y);
    EXPECT_NEAR(points[3 * k + 2], v.z - 0.3, 1e-16);
  }
}

const char* const kPlane = R"(walls:
  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, material: glass}
)";

TEST(VtkSeries, FramesAndCollectionsStaticWallsWrittenOnce) {
  const std::string dir = test_directory("static");
  const Scene scene = scene_with(kPlane);
  VtkSeriesWriter writer(scene, dir + "/pv", VtkParticles::surfaces);
  const std::vector<TrajectoryRow> rows = {row(0, 0, {0, 0, 0.05})};
  writer.write_frame(0, 0.0, rows);
  writer.write_frame(10, 0.01, rows);
  writer.write_frame(15, 0.015, rows);
  EXPECT_EQ(file_names(dir + "/pv"),
            (std::vector<std::string>{"particles.pvd", "particles_000000000.vtp",
                                      "particles_000000010.vtp", "particles_000000015.vtp",
                                      "walls.pvd", "walls_000000000.vtp"}));
  const std::string particles = read_text(dir + "/pv/particles.pvd");
  EXPECT_NE(particles.find("timestep=\"0.01\" part=\"0\" file=\"particles_000000010.vtp\""),
            std::string::npos);
  EXPECT_NE(particles.find("timestep=\"0.014999999999999999\" part=\"0\" "
                           "file=\"particles_000000015.vtp\""),
            std::string::npos);
  // Each frame lists the one walls file.
  const std::string walls = read_text(dir + "/pv/walls.pvd");
  EXPECT_NE(walls.find("timestep=\"0.01\" part=\"0\" file=\"walls_000000000.vtp\""),
            std::string::npos);
  EXPECT_NE(walls.find("timestep=\"0.014999999999999999\" part=\"0\" file=\"walls_000000000.vtp\""),
            std::string::npos);
  const std::string frame = read_text(dir + "/pv/particles_000000015.vtp");
  EXPECT_NE(frame.find("NumberOfPoints=\"20\""), std::string::npos);  // a dodecahedron
  EXPECT_NE(frame.find("NumberOfPolys=\"12\""), std::string::npos);
}

TEST(VtkSeries, MovingWallsAndOpenedOutletsGetNewWallFiles) {
  const std::string dir = test_directory("moving");
  const Scene moving = scene_with(
      "walls:\n  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, material: glass,\n"
      "            motion: {translation: {velocity: [0, 0, 1]}}}\n");
  VtkSeriesWriter writer(moving, dir + "/moving", VtkParticles::points);
  for (int step = 0; step < 3; ++step) writer.write_frame(step, 0.1 * step, {});
  EXPECT_TRUE(fs::exists(dir + "/moving/walls_000000002.vtp"));
  EXPECT_NE(read_text(dir + "/moving/particles_000000000.vtp").find("NumberOfPoints=\"0\""),
            std::string::npos);  // no particles: an empty piece, still valid
  const Scene outlet = scene_with(R"(walls:
  - hopper: {base: [0, 0, 0], bottom_radius: 0.01, top_radius: 0.05, height: 0.05,
             outlet: closed, outlet_opens_at: 0.25, segments: 8, material: glass}
)");
  VtkSeriesWriter opening(outlet, dir + "/outlet", VtkParticles::points);
  for (int step = 0; step < 4; ++step) opening.write_frame(step, 0.1 * step, {});
  // Written at the start and when the outlet opened (t = 0.3), not in between.
  const std::vector<std::string> names = file_names(dir + "/outlet");
  EXPECT_EQ(std::count_if(names.begin(), names.end(),
                          [](const std::string& n) { return n.rfind("walls_", 0) == 0; }),
            2);
  EXPECT_TRUE(fs::exists(dir + "/outlet/walls_000000003.vtp"));
}

// A frame that cannot be written (its temporary name is taken by a directory) throws, naming the
// file, and leaves the collections listing the frames before it, as an interrupted run would.
TEST(VtkSeries, AFailedFrameLeavesTheSeriesOfTheFramesBefore) {
  const std::string dir = test_directory("interrupted");
  const Scene scene = scene_with(kPlane);
  VtkSeriesWriter writer(scene, dir, VtkParticles::points);
  writer.write_frame(0, 0.0, {row(0, 0, {0, 0, 0.05})});
  writer.write_frame(1, 0.5, {row(0, 0, {0, 0, 0.04})});
  const std::string particles = read_text(dir + "/particles.pvd");
  const std::string walls = read_text(dir + "/walls.pvd");
  fs::create_directory(dir + "/particles_000000002.vtp.tmp");
  try {
    writer.write_frame(2, 1.0, {row(0, 0, {0, 0, 0.03})});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind("cannot write '" + dir + "/particles_000000002.vtp': ", 0), 0u)
        << e.what();
  }
  EXPECT_EQ(read_text(dir + "/particles.pvd"), particles);
  EXPECT_EQ(read_text(dir + "/walls.pvd"), walls);
  EXPECT_NE(particles.find("particles_000000001.vtp"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/particles_000000002.vtp"));
}

}  // namespace
}  // namespace talus
