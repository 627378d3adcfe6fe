#include "solver/scene/scene.hpp"

#include <cmath>
#include <optional>

namespace talus {

std::string SourceRef::where() const {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line) + ":" + std::to_string(column);
  return key.empty() ? text : text + ": " + key;
}

double Region::volume() const {
  if (kind == RegionKind::cylinder) return M_PI * radius * radius * height;
  const Vec3d size = box_max - box_min;
  return size.x * size.y * size.z;
}

double WallMotion::angular_speed() const {
  return rpm * 2 * M_PI / 60;
}

namespace {
// The oscillation's phase 2 pi f (t - start) while it runs; nullopt before and after.
std::optional<double> oscillation_phase(const WallMotion& m, double time) {
  if (m.kind != WallMotion::Kind::oscillation || !(time > m.start)) return std::nullopt;
  const double elapsed = time - m.start;
  if (m.cycles > 0 && elapsed * m.frequency >= m.cycles) return std::nullopt;
  return 2 * M_PI * m.frequency * elapsed;
}
}  // namespace

double WallMotion::oscillation_displacement(double time) const {
  const std::optional<double> phase = oscillation_phase(*this, time);
  return phase ? amplitude * (1 - std::cos(*phase)) : 0;
}

double WallMotion::oscillation_speed(double time) const {
  const std::optional<double> phase = oscillation_phase(*this, time);
  return phase ? amplitude * 2 * M_PI * frequency * std::sin(*phase) : 0;
}

int Scene::material_index(const std::string& name) const {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == name) return int(i);
  return -1;
}

int Scene::template_index(const std::string& name) const {
  for (std::size_t i = 0; i < templates.size(); ++i)
    if (templates[i].name == name) return int(i);
  return -1;
}

namespace {

const MaterialPair* find_pair(const std::vector<MaterialPair>& pairs, int a, int b) {
  if (a > b) std::swap(a, b);
  for (const MaterialPair& pair : pairs)
    if (pair.material_a == a && pair.material_b == b) return &pair;
  return nullptr;
}

}  // namespace

double Scene::pair_friction(int material_a, int material_b) const {
  const MaterialPair* pair = find_pair(material_pairs, material_a, material_b);
  if (pair && pair->friction) return *pair->friction;
  return 0.5 * (materials[material_a].friction + materials[material_b].friction);
}

double Scene::pair_restitution(int material_a, int material_b) const {
  const MaterialPair* pair = find_pair(material_pairs, material_a, material_b);
  if (pair && pair->restitution) return *pair->restitution;
  return 0.5 * (materials[material_a].restitution + materials[material_b].restitution);
}

const char* to_string(WallKind kind) {
  switch (kind) {
    case WallKind::mesh:
      return "mesh";
    case WallKind::plane:
      return "plane";
    case WallKind::box:
      return "box";
    case WallKind::cylinder:
      return "cylinder";
    case WallKind::drum:
      return "drum";
    case WallKind::hopper:
      return "hopper";
    case WallKind::silo:
      return "silo";
  }
  return "?";
}

const char* to_string(ContactModel model) {
  switch (model) {
    case ContactModel::volume:
      return "volume";
    case ContactModel::volume_paper:
      return "volume_paper";
    case ContactModel::linear:
      break;
  }
  return "linear";
}

const char* to_string(Probe probe) {
  switch (probe) {
    case Probe::kinetic_energy:
      return "kinetic_energy";
    case Probe::wall_forces:
      return "wall_forces";
    case Probe::contact_count:
      return "contact_count";
    case Probe::bed_height:
      return "bed_height";
    case Probe::energy:
      return "energy";
  }
  return "?";
}

const char* to_string(Backend backend) {
  switch (backend) {
    case Backend::automatic:
      return "auto";
    case Backend::cpu:
      return "cpu";
    case Backend::cuda:
      return "cuda";
  }
  return "?";
}

const char* to_string(Precision precision) {
  return precision == Precision::float32 ? "float" : "double";
}

const char* to_string(VtkParticles particles) {
  return particles == VtkParticles::surfaces ? "surfaces" : "points";
}

}  // namespace talus
