// The `particles` section: an explicit list, lattices, random fills and feeds. Only the requests
// are stored; the solver places the particles.
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <sstream>

#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_sections.hpp"

namespace talus {
namespace {

// Random sequential addition of equal spheres jams at a volume fraction of 0.384 (Torquato,
// Uche & Stillinger, Phys. Rev. E 74, 2006): a random fill asking its bounding spheres for more
// of the region than that cannot be placed.
constexpr double kRandomPlacementLimit = 0.38;

const std::string kPosition = "a position [x, y, z] in m";
const std::string kVelocity = "a velocity [x, y, z] in m/s";

std::string metres(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value << " m";
  return out.str();
}

Region parse_region(const SceneNode& node, bool box_only) {
  const auto [kind, body] = node.one_of(
      box_only ? std::vector<std::string>{"box"} : std::vector<std::string>{"box", "cylinder"},
      "region");
  Region region;
  if (kind == "box") {
    body.keys({"min", "max"}, "a box region: a map with keys min, max");
    region.kind = RegionKind::box;
    region.box_min = body.at("min", "the box's lowest corner [x, y, z] in m")
                         .vec3("the box's lowest corner [x, y, z] in m");
    const SceneNode max = body.at("max", "the box's highest corner [x, y, z] in m");
    const std::string expected_max = "a corner [x, y, z] in m above min on every axis";
    region.box_max = max.vec3(expected_max);
    for (int k = 0; k < 3; ++k)
      if (!(region.box_max[k] > region.box_min[k])) max.fail_expected(expected_max);
    return region;
  }
  body.keys({"base", "axis", "radius", "height"},
            "a cylinder region: a map with keys base, axis, radius, height");
  region.kind = RegionKind::cylinder;
  region.base = body.at("base", "the centre of the bottom disc [x, y, z] in m")
                    .vec3("the centre of the bottom disc [x, y, z] in m");
  if (auto axis = body.find("axis")) region.axis = axis->direction("the cylinder's axis");
  region.radius = body.at("radius", "a positive number in m").positive("m");
  region.height = body.at("height", "a positive number in m").positive("m");
  return region;
}

// The region must hold one bounding sphere of the template.
void check_region_fits(const SceneNode& node, const Region& region, const ParticleTemplate& t) {
  const double diameter = 2 * t.bounding_radius;
  bool fits = region.kind == RegionKind::box
                  ? (region.box_max.x - region.box_min.x >= diameter &&
                     region.box_max.y - region.box_min.y >= diameter &&
                     region.box_max.z - region.box_min.z >= diameter)
                  : (region.radius >= t.bounding_radius && region.height >= diameter);
  if (!fits)
    node.fail("expected a region that holds one bounding sphere of template '" + t.name +
              "' (diameter " + metres(diameter) + ")");
}

bool optional_bool(const SceneNode& body, const std::string& key, bool fallback) {
  const std::optional<SceneNode> node = body.find(key);
  return node ? node->boolean() : fallback;
}

Vec3d optional_velocity(const SceneNode& body) {
  const std::optional<SceneNode> node = body.find("velocity");
  return node ? node->vec3(kVelocity) : Vec3d();
}

// An entry's seed: its own, else the scene's plus the entry's place in the list plus one.
std::uint64_t entry_seed(const SceneNode& body, const Scene& scene, std::size_t index) {
  const std::optional<SceneNode> node = body.find("seed");
  if (node) return std::uint64_t(node->integer(kSeedExpected, 0, kMaxSeed));
  return scene.seed + index + 1;
}

void parse_explicit(const SceneNode& node, Scene& scene) {
  const std::vector<SceneNode> items = node.items("a list of particles");
  if (items.empty()) node.fail_expected("a list of particles (at least one)");
  for (const SceneNode& item : items) {
    item.keys({"template", "position", "orientation", "velocity", "angular_velocity"},
              "a particle: a map with keys template, position, orientation, velocity, "
              "angular_velocity");
    ParticleState particle;
    particle.template_index = template_reference(item.at("template", "a template name"), scene);
    particle.position = item.at("position", kPosition).vec3(kPosition);
    if (auto orientation = item.find("orientation"))
      particle.orientation = orientation->orientation();
    particle.velocity = optional_velocity(item);
    if (auto spin = item.find("angular_velocity"))
      particle.angular_velocity = spin->vec3("an angular velocity [x, y, z] in rad/s");
    particle.source = item.ref();
    scene.particles.push_back(particle);
  }
}

void parse_lattice(const SceneNode& body, Scene& scene, std::size_t index) {
  body.keys({"template", "region", "spacing", "velocity", "random_orientation", "seed"},
            "a lattice: a map with keys template, region, spacing, velocity, "
            "random_orientation, seed");
  LatticeRequest lattice;
  lattice.template_index = template_reference(body.at("template", "a template name"), scene);
  const ParticleTemplate& t = scene.templates[lattice.template_index];
  const SceneNode region = body.at("region", "a box region {box: {min, max}}");
  lattice.region = parse_region(region, true);
  const SceneNode spacing = body.at("spacing", "a spacing in m, one number or [x, y, z]");
  const double diameter = 2 * t.bounding_radius;
  const std::string expected_spacing =
      "a spacing in m, one number or [x, y, z], each at least the bounding diameter " +
      metres(diameter) + " of template '" + t.name + "' so that particles do not overlap";
  lattice.spacing = spacing.is_list() ? spacing.vec3(expected_spacing)
                                      : Vec3d(1, 1, 1) * spacing.number(expected_spacing);
  // Touching neighbours are allowed: a spacing written equal to the diameter passes despite
  // the round-off of the bounding radius computed from the vertices (~1e-16 relative).
  for (int k = 0; k < 3; ++k)
    if (!(lattice.spacing[k] >= diameter * (1 - 1e-9))) spacing.fail_expected(expected_spacing);
  const Vec3d size = lattice.region.box_max - lattice.region.box_min;
  for (int k = 0; k < 3; ++k)
    if (size[k] < lattice.spacing[k])
      region.fail(
          "expected a box at least one spacing wide on every axis, to hold a lattice "
          "point");
  // Counted in doubles and refused before any integer holds the count (8e9 points overflow int).
  const std::array<double, 3> n = lattice_dimensions(lattice.region, lattice.spacing);
  const double points = n[0] * n[1] * n[2];
  if (points > double(kMaxParticles))
    spacing.fail(
        fmt::format("a lattice of {:.0f} x {:.0f} x {:.0f} = {:.4g} points, above the "
                    "limit of {} particles in a scene; use a larger spacing or a "
                    "smaller box",
                    n[0], n[1], n[2], points, describe_limit(kMaxParticles)));
  lattice.velocity = optional_velocity(body);
  lattice.random_orientation = optional_bool(body, "random_orientation", false);
  lattice.seed = entry_seed(body, scene, index);
  lattice.source = body.ref();
  scene.lattices.push_back(lattice);
}

void parse_random_fill(const SceneNode& body, Scene& scene, std::size_t index) {
  body.keys(
      {"template", "region", "count", "volume_fraction", "velocity", "random_orientation", "seed"},
      "a random fill: a map with keys template, region, count or volume_fraction, "
      "velocity, random_orientation, seed");
  RandomFillRequest fill;
  fill.template_index = template_reference(body.at("template", "a template name"), scene);
  const ParticleTemplate& t = scene.templates[fill.template_index];
  const SceneNode region = body.at("region", "a region {box: ...} or {cylinder: ...}");
  fill.region = parse_region(region, false);
  check_region_fits(region, fill.region, t);
  const std::optional<SceneNode> count = body.find("count"),
                                 fraction = body.find("volume_fraction");
  if (count.has_value() == fraction.has_value())
    body.fail(
        "expected either count (a number of particles) or volume_fraction (particle "
        "volume over region volume), got " +
        std::string(count ? "both" : "neither"));
  const SceneNode& amount = count ? *count : *fraction;
  if (count) {
    fill.count = count->integer("a positive integer number of particles", 1, kMaxParticles);
  } else {
    fill.volume_fraction =
        fraction->number("a number in (0, 1) (particle volume over region volume)",
                         [](double v) { return v > 0 && v < 1; });
    const double particles = std::round(fill.volume_fraction * fill.region.volume() / t.volume);
    if (!(particles <= double(kMaxParticles)))
      fraction->fail(
          fmt::format("a volume fraction of {} of this region is {:.4g} particles of "
                      "template '{}', above the limit of {} particles in a scene",
                      fraction->text(""), particles, t.name, describe_limit(kMaxParticles)));
    fill.count = static_cast<long long>(particles);
    if (fill.count < 1)
      fraction->fail("a volume fraction of " + fraction->text("") +
                     " of this region is less than one particle of template '" + t.name + "'");
  }
  const double sphere_fraction =
      double(fill.count) * 4.0 / 3.0 * M_PI * std::pow(t.bounding_radius, 3) / fill.region.volume();
  if (sphere_fraction > kRandomPlacementLimit) {
    std::ostringstream message;
    message.precision(3);
    message << fill.count << " particles of template '" << t.name
            << "' need bounding spheres filling " << sphere_fraction
            << " of the region; random placement jams near " << kRandomPlacementLimit
            << ": ask for fewer or a larger region";
    amount.fail(message.str());
  }
  fill.velocity = optional_velocity(body);
  fill.random_orientation = optional_bool(body, "random_orientation", true);
  fill.seed = entry_seed(body, scene, index);
  fill.source = body.ref();
  scene.random_fills.push_back(fill);
}

void parse_feed(const SceneNode& body, Scene& scene, std::size_t index) {
  body.keys(
      {"template", "region", "rate", "start", "stop", "velocity", "random_orientation", "seed"},
      "a feed: a map with keys template, region, rate, start, stop, velocity, "
      "random_orientation, seed");
  FeedRequest feed;
  feed.template_index = template_reference(body.at("template", "a template name"), scene);
  const SceneNode region = body.at("region", "a region {box: ...} or {cylinder: ...}");
  feed.region = parse_region(region, false);
  check_region_fits(region, feed.region, scene.templates[feed.template_index]);
  feed.rate =
      body.at("rate", "a positive number in particles per second").positive("particles per second");
  const std::string expected_start = "a non-negative number in s, before the end time";
  if (auto start = body.find("start"))
    feed.start =
        start->number(expected_start, [&](double v) { return v >= 0 && v < scene.end_time; });
  feed.stop = scene.end_time;
  if (auto stop = body.find("stop"))
    feed.stop = stop->number("a number in s after start", [&](double v) { return v > feed.start; });
  // Feeder::due converts rate x time to an integer: bounded here, in doubles, before it can
  // overflow.
  const double total = feed_particle_count(feed.rate, feed.start, feed.stop);
  if (total > double(kMaxParticles))
    body.at("rate", "")
        .fail(fmt::format(
            "{:.6g} particles per second from {:.6g} s to {:.6g} s is {:.4g} particles, above the "
            "limit of {} particles in a scene",
            feed.rate, feed.start, feed.stop, total, describe_limit(kMaxParticles)));
  feed.velocity = optional_velocity(body);
  feed.random_orientation = optional_bool(body, "random_orientation", true);
  feed.seed = entry_seed(body, scene, index);
  feed.source = body.ref();
  scene.feeds.push_back(feed);
}

}  // namespace

void parse_particles(const SceneNode& node, Scene& scene) {
  const std::vector<std::string> kinds = {"explicit", "lattice", "random", "feed"};
  const std::vector<SceneNode> items = node.items(
      "a list of particle entries ({explicit: [...]}, {lattice: ...}, {random: ...}, "
      "{feed: ...})");
  if (items.empty()) node.fail_expected("a list of particle entries (at least one)");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const auto [kind, body] = items[i].one_of(kinds, "particle entry");
    if (kind == "explicit") parse_explicit(body, scene);
    if (kind == "lattice") parse_lattice(body, scene, i);
    if (kind == "random") parse_random_fill(body, scene, i);
    if (kind == "feed") parse_feed(body, scene, i);
    const double total = scene_particle_count(scene);
    if (total > double(kMaxParticles))
      body.fail(
          fmt::format("this entry brings the scene to {:.4g} particles (initial ones and all "
                      "that feeds insert), above the limit of {} particles in a scene",
                      total, describe_limit(kMaxParticles)));
  }
}

}  // namespace talus
