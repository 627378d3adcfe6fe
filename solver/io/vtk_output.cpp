#include "solver/io/vtk_output.hpp"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "solver/io/output_files.hpp"

namespace talus {
namespace {

constexpr double kPi = 3.14159265358979323846;

void add_vec3(VtkArray& array, const Vec3d& v) {
  array.add(v.x);
  array.add(v.y);
  array.add(v.z);
}

// Vertices: the north pole, kSphereBands - 1 rings of kSphereSegments, the south pole.
TemplateSurface sphere_surface(double radius) {
  TemplateSurface s;
  s.vertices.push_back({0, 0, radius});
  for (int band = 1; band < kSphereBands; ++band) {
    const double polar = kPi * band / kSphereBands;
    for (int k = 0; k < kSphereSegments; ++k) {
      const double azimuth = 2 * kPi * k / kSphereSegments;
      s.vertices.push_back({radius * std::sin(polar) * std::cos(azimuth),
                            radius * std::sin(polar) * std::sin(azimuth),
                            radius * std::cos(polar)});
    }
  }
  const int south = static_cast<int>(s.vertices.size());
  s.vertices.push_back({0, 0, -radius});
  auto ring = [](int band, int k) {
    return 1 + (band - 1) * kSphereSegments + k % kSphereSegments;
  };
  for (int k = 0; k < kSphereSegments; ++k) {
    s.faces.push_back({0, ring(1, k), ring(1, k + 1)});
    for (int band = 1; band + 1 < kSphereBands; ++band)
      s.faces.push_back(
          {ring(band, k), ring(band + 1, k), ring(band + 1, k + 1), ring(band, k + 1)});
    s.faces.push_back({ring(kSphereBands - 1, k), south, ring(kSphereBands - 1, k + 1)});
  }
  return s;
}

}  // namespace

VtkParticles vtk_particles_for(const Scene& scene, std::size_t initial_particles) {
  if (scene.outputs.vtk && scene.outputs.vtk->particles) return *scene.outputs.vtk->particles;
  double most = static_cast<double>(initial_particles);
  for (const FeedRequest& feed : scene.feeds)
    most += std::floor(feed.rate * (feed.stop - feed.start));
  return most <= double(kVtkSurfaceParticleLimit) ? VtkParticles::surfaces : VtkParticles::points;
}

TemplateSurface template_surface(const ParticleTemplate& t) {
  if (t.kind == ParticleShapeKind::sphere) return sphere_surface(t.sphere_radius);
  TemplateSurface s;
  s.vertices = t.shape.vertices;
  for (const Face& face : t.shape.faces) s.faces.push_back(face.loop);
  return s;
}

VtkPolyData particle_surfaces(const std::vector<TemplateSurface>& surfaces,
                              const std::vector<TrajectoryRow>& rows) {
  VtkPolyData data;
  VtkArray id("id", VtkArray::Type::int64), template_id("template", VtkArray::Type::int32);
  VtkArray velocity("velocity", VtkArray::Type::float64, 3);
  VtkArray angular_velocity("angular_velocity", VtkArray::Type::float64, 3);
  std::vector<std::int64_t> loop;
  for (const TrajectoryRow& row : rows) {
    const TemplateSurface& surface = surfaces.at(row.template_index);
    const auto first = static_cast<std::int64_t>(data.point_count());
    for (const Vec3d& v : surface.vertices)
      add_vec3(data.points, row.position + rotate(row.orientation, v));
    for (const std::vector<int>& face : surface.faces) {
      loop.clear();
      for (const int k : face) loop.push_back(first + k);
      data.add_polygon(loop);
      id.add(std::int64_t(row.id));
      template_id.add(std::int32_t(row.template_index));
      add_vec3(velocity, row.velocity);
      add_vec3(angular_velocity, row.angular_velocity);
    }
  }
  data.cell_data = {id, template_id, velocity, angular_velocity};
  return data;
}

VtkPolyData particle_points(const Scene& scene, const std::vector<TrajectoryRow>& rows) {
  VtkPolyData data;
  VtkArray id("id", VtkArray::Type::int64), template_id("template", VtkArray::Type::int32);
  VtkArray orientation("orientation", VtkArray::Type::float64, 4);
  VtkArray velocity("velocity", VtkArray::Type::float64, 3);
  VtkArray angular_velocity("angular_velocity", VtkArray::Type::float64, 3);
  VtkArray bounding_radius("bounding_radius", VtkArray::Type::float64);
  for (const TrajectoryRow& row : rows) {
    data.vertex_cells.push_back(static_cast<std::int64_t>(data.point_count()));
    add_vec3(data.points, row.position);
    id.add(std::int64_t(row.id));
    template_id.add(std::int32_t(row.template_index));
    for (const double q :
         {row.orientation.w, row.orientation.x, row.orientation.y, row.orientation.z})
      orientation.add(q);
    add_vec3(velocity, row.velocity);
    add_vec3(angular_velocity, row.angular_velocity);
    bounding_radius.add(scene.templates.at(row.template_index).bounding_radius);
  }
  data.point_data = {id, template_id, orientation, velocity, angular_velocity, bounding_radius};
  return data;
}

VtkPolyData wall_polygons(const Scene& scene, const std::vector<WallMesh>& meshes, double time) {
  VtkPolyData data;
  VtkArray wall("wall", VtkArray::Type::int32);
  const std::vector<TriangleMesh> walls = walls_at(scene, meshes, time);
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const auto first = static_cast<std::int64_t>(data.point_count());
    for (const Vec3d& v : walls[w].vertices) add_vec3(data.points, v);
    for (const auto& corners : walls[w].triangles) {
      data.add_polygon({first + corners[0], first + corners[1], first + corners[2]});
      wall.add(std::int32_t(w));
    }
  }
  data.cell_data = {wall};
  return data;
}

VtkSeriesWriter::VtkSeriesWriter(const Scene& scene, std::string directory, VtkParticles particles)
    : scene_(scene),
      directory_(std::move(directory)),
      particles_(particles),
      meshes_(make_wall_meshes(scene)),
      written_triangles_(scene.walls.size(), -1) {
  create_output_directory(directory_, "ParaView directory (outputs.vtk.directory)");
  if (particles_ == VtkParticles::surfaces)
    for (const ParticleTemplate& t : scene.templates) surfaces_.push_back(template_surface(t));
}

void VtkSeriesWriter::write_frame(long long step, double time,
                                  const std::vector<TrajectoryRow>& rows) {
  const std::string file = numbered_file_name("particles_", step, ".vtp");
  const VtkPolyData data = particles_ == VtkParticles::surfaces ? particle_surfaces(surfaces_, rows)
                                                                : particle_points(scene_, rows);
  write_file_atomically(directory_ + "/" + file, vtp_text(data));
  particle_frames_.push_back({time, file});
  if (!meshes_.empty()) write_walls(step, time);
  write_file_atomically(directory_ + "/particles.pvd", pvd_text(particle_frames_));
  if (!meshes_.empty()) write_file_atomically(directory_ + "/walls.pvd", pvd_text(wall_frames_));
}

// A new walls file when a wall moves or a wall's present triangles changed (an outlet opened);
// otherwise this frame lists the last one again.
void VtkSeriesWriter::write_walls(long long step, double time) {
  std::vector<int> triangles;
  for (std::size_t w = 0; w < meshes_.size(); ++w)
    triangles.push_back(present_triangle_count(scene_.walls[w], meshes_[w], time));
  if (scene_.effects.moving_walls || triangles != written_triangles_) {
    walls_file_ = numbered_file_name("walls_", step, ".vtp");
    write_file_atomically(directory_ + "/" + walls_file_,
                          vtp_text(wall_polygons(scene_, meshes_, time)));
    written_triangles_ = triangles;
  }
  wall_frames_.push_back({time, walls_file_});
}

// Lines: "particles <count>" and a "<time> <file>" line per frame, the same for "walls", then
// "walls_file <name or ->" and "written <per wall: triangles>". Times with 17 digits: exact.
std::string VtkSeriesWriter::save() const {
  std::ostringstream out;
  for (const auto* frames : {&particle_frames_, &wall_frames_}) {
    out << (frames == &particle_frames_ ? "particles " : "walls ") << frames->size() << "\n";
    for (const PvdEntry& e : *frames) out << exact_decimal(e.time) << " " << e.file << "\n";
  }
  out << "walls_file " << (walls_file_.empty() ? "-" : walls_file_) << "\nwritten";
  for (const int t : written_triangles_) out << " " << t;
  out << "\n";
  return out.str();
}

void VtkSeriesWriter::restore(const std::string& state) {
  std::istringstream in(state);
  const auto fail = [&]() {
    throw std::runtime_error(directory_ + ": the checkpoint's ParaView series state is not one");
  };
  std::vector<PvdEntry> frames[2];
  for (int k = 0; k < 2; ++k) {
    std::string word;
    std::size_t count = 0;
    if (!(in >> word >> count) || word != (k == 0 ? "particles" : "walls")) fail();
    for (std::size_t f = 0; f < count; ++f) {
      std::string time, file;
      PvdEntry e;
      if (!(in >> time >> file) || !parse_double(time, e.time)) fail();
      e.file = file;
      frames[k].push_back(e);
    }
  }
  std::string word, file;
  if (!(in >> word >> file) || word != "walls_file" || !(in >> word) || word != "written") fail();
  std::vector<int> written(written_triangles_.size());
  for (int& t : written)
    if (!(in >> t)) fail();
  particle_frames_ = frames[0];
  wall_frames_ = frames[1];
  walls_file_ = file == "-" ? "" : file;
  written_triangles_ = written;
}

}  // namespace talus
