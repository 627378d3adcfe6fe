// The initial particles of a scene: order and ids, lattices at their closed-form points, random
// fills inside their regions without overlaps (checked by brute force), reproducible from the
// seed, uniform orientations, the placement grid against brute force, and the error of a fill
// that cannot be placed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "solver/scene/initial_particles.hpp"
#include "solver/scene/placement.hpp"
#include "tests/scene/scene_test_util.hpp"
#include "tests/scene/wall_test_util.hpp"

namespace talus {
namespace {

const std::string kPreamble = R"(time: {step: 1.0e-5, end: 0.1}
seed: 11
materials:
  glass: {density: 2500, youngs_modulus: 6.0e7, poisson_ratio: 0.23, friction: 0.4,
          restitution: 0.8}
templates:
  grain: {shape: dodecahedron:0.01, material: glass}
  ball: {sphere: 0.002, material: glass}
effects: {contact: volume}
)";

Scene scene_of(const std::string& rest) {
  return parse_scene(kPreamble + rest, "fill.yaml", scene_data_dir());
}

double bounding_radius(const Scene& scene, const ParticleState& p) {
  return scene.templates[p.template_index].bounding_radius;
}

bool same_bits(const ParticleState& a, const ParticleState& b) {
  const double x[] = {a.position.x,    a.position.y,    a.position.z,   a.orientation.w,
                      a.orientation.x, a.orientation.y, a.orientation.z};
  const double y[] = {b.position.x,    b.position.y,    b.position.z,   b.orientation.w,
                      b.orientation.x, b.orientation.y, b.orientation.z};
  return a.template_index == b.template_index && std::memcmp(x, y, sizeof x) == 0;
}

// Brute force: no two bounding spheres overlap (touching allowed, as in the placement).
void expect_no_overlaps(const Scene& scene, const std::vector<ParticleState>& particles,
                        std::size_t from = 0) {
  for (std::size_t i = from; i < particles.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      const double reach =
          bounding_radius(scene, particles[i]) + bounding_radius(scene, particles[j]);
      ASSERT_GE(norm(particles[i].position - particles[j].position), reach)
          << "particles " << j << " and " << i;
    }
}

TEST(InitialParticles, ExplicitThenLatticesThenFillsInSceneOrder) {
  const Scene scene = scene_of(R"(particles:
  - random:
      template: ball
      region: {box: {min: [0.2, 0, 0], max: [0.3, 0.1, 0.1]}}
      count: 30
  - explicit:
      - {template: grain, position: [0, 0, 0.05], velocity: [1, 2, 3]}
  - lattice:
      template: ball
      region: {box: {min: [-0.1, -0.1, 0], max: [-0.07, -0.08, 0.004]}}
      spacing: [0.01, 0.005, 0.004]
      velocity: [0, 0, -1]
  - explicit:
      - {template: ball, position: [0.1, 0, 0.05]}
)");
  const std::vector<ParticleState> particles = initial_particles(scene);
  // 2 explicit, a lattice of floor(0.03/0.01) x floor(0.02/0.005) x floor(0.004/0.004) = 3x4x1
  // (the last two exact multiples of the spacing, kept despite round-off), then the fill.
  ASSERT_EQ(particles.size(), 2u + 12u + 30u);
  EXPECT_EQ(particles[0].template_index, scene.template_index("grain"));
  EXPECT_EQ(particles[0].velocity.y, 2);
  EXPECT_EQ(particles[1].position.x, 0.1);
  for (std::size_t i = 2; i < 14; ++i) {
    EXPECT_EQ(particles[i].velocity.z, -1);
    EXPECT_EQ(particles[i].source.key, scene.lattices[0].source.key);
  }
  for (std::size_t i = 14; i < particles.size(); ++i) {
    EXPECT_GE(particles[i].position.x, 0.2);
    EXPECT_EQ(particles[i].source.key, scene.random_fills[0].source.key);
  }
}

// A resumed run counts the initial particles (they shape its VTK output) without placing them,
// and builds its step from the scene without them (production_run.cpp).
TEST(InitialParticles, CountedWithoutPlacingAndTakenOutForAResume) {
  const Scene scene = scene_of(R"(particles:
  - random:
      template: ball
      region: {box: {min: [0.2, 0, 0], max: [0.3, 0.1, 0.1]}}
      count: 30
  - explicit:
      - {template: grain, position: [0, 0, 0.05]}
      - {template: ball, position: [0.1, 0, 0.05]}
  - lattice:
      template: ball
      region: {box: {min: [-0.05, 0.01, 0], max: [0.05, 0.04, 0.035]}}
      spacing: [0.012, 0.01, 0.012]
  - feed:
      template: ball
      region: {box: {min: [0.2, 0, 0.2], max: [0.3, 0.1, 0.3]}}
      rate: 100
      stop: 0.05
)");
  // The count is exact: the placement's own size. The lattice (8 x 3 x 2, the test below) has
  // round-off at its edges that a separate count could get wrong by a row.
  EXPECT_EQ(initial_particle_count(scene), initial_particles(scene).size());
  EXPECT_EQ(initial_particle_count(scene), 30u + 2u + 48u);
  const Scene start = without_initial_particles(scene);
  EXPECT_EQ(initial_particle_count(start), 0u);
  EXPECT_TRUE(initial_particles(start).empty());
  // The rest stays: templates, feeds, the time step.
  EXPECT_EQ(start.templates.size(), scene.templates.size());
  EXPECT_EQ(start.feeds.size(), 1u);
  EXPECT_EQ(start.time_step, scene.time_step);
}

TEST(InitialParticles, LatticePointsAreMinPlusSpacingTimesHalfIntegers) {
  LatticeRequest lattice;
  lattice.template_index = 0;
  lattice.region.box_min = {-0.05, 0.01, 0};
  lattice.region.box_max = {0.05, 0.04, 0.035};
  lattice.spacing = {0.012, 0.01, 0.012};
  const std::vector<ParticleState> points = lattice_particles(lattice);
  // floor(0.1 / 0.012) = 8, floor(0.03 / 0.01) = 3, floor(0.035 / 0.012) = 2.
  ASSERT_EQ(points.size(), 8u * 3u * 2u);
  std::size_t i = 0;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 8; ++x, ++i) {
        // Each coordinate is one product and one sum, as written: exact agreement expected.
        EXPECT_EQ(points[i].position.x, -0.05 + 0.012 * (x + 0.5));
        EXPECT_EQ(points[i].position.y, 0.01 + 0.01 * (y + 0.5));
        EXPECT_EQ(points[i].position.z, 0 + 0.012 * (z + 0.5));
        EXPECT_EQ(points[i].orientation.w, 1);  // random_orientation is off
      }
  lattice.random_orientation = true;
  for (const ParticleState& p : lattice_particles(lattice))
    EXPECT_NEAR(p.orientation.norm(), 1, 1e-15);  // one normalisation: an ulp or two
}

TEST(InitialParticles, RandomFillsStayInsideTheirRegionsAndOffEverything) {
  const Scene scene = scene_of(R"(particles:
  - explicit:
      - {template: grain, position: [0, 0, 0.03]}
  - random:
      template: ball
      region: {box: {min: [-0.03, -0.03, 0], max: [0.03, 0.03, 0.06]}}
      count: 600
  - random:
      template: grain
      region: {cylinder: {base: [0, 0, 0.01], axis: [1, 1, 0], radius: 0.03, height: 0.05}}
      count: 20
walls:
  - plane: {point: [0, 0, 0.02], normal: [0, 0, 1], size: 0.04, material: glass}
  - cylinder: {base: [0, 0, -0.01], radius: 0.045, height: 0.1, bottom_cap: true, material: glass}
)");
  const std::vector<ParticleState> particles = initial_particles(scene);
  ASSERT_EQ(particles.size(), 621u);
  expect_no_overlaps(scene, particles);
  const std::vector<WallMesh> walls = make_wall_meshes(scene);
  const Region& box = scene.random_fills[0].region;
  const Region& cylinder = scene.random_fills[1].region;
  for (std::size_t i = 1; i < particles.size(); ++i) {
    const ParticleState& p = particles[i];
    const double r = bounding_radius(scene, p);
    if (i <= 600) {
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(p.position[k] - r, box.box_min[k]);
        EXPECT_LE(p.position[k] + r, box.box_max[k]);
      }
    } else {
      // Inside the cylinder: along the axis in [r, h - r], off it by at most R - r; 1e-15 m
      // allows the round-off of these few products.
      const Vec3d d = p.position - cylinder.base;
      const double along = dot(d, cylinder.axis);
      EXPECT_GE(along, r - 1e-15);
      EXPECT_LE(along, cylinder.height - r + 1e-15);
      EXPECT_LE(norm(d - cylinder.axis * along), cylinder.radius - r + 1e-15);
    }
    EXPECT_NEAR(p.orientation.norm(), 1, 1e-15);
    for (const WallMesh& wall : walls)
      for (const auto& t : wall.mesh.triangles)
        ASSERT_GE(point_triangle_distance2(p.position, wall.mesh.vertices[t[0]],
                                           wall.mesh.vertices[t[1]], wall.mesh.vertices[t[2]]),
                  r * r)
            << "particle " << i << " cuts a wall";
  }
}

TEST(InitialParticles, SameSceneSameBitsAndTheSeedMatters) {
  const std::string fill = R"(particles:
  - random:
      template: grain
      region: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}}
      count: 200
)";
  const std::vector<ParticleState> a = initial_particles(scene_of(fill));
  const std::vector<ParticleState> b = initial_particles(scene_of(fill));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(same_bits(a[i], b[i])) << i;
  const std::vector<ParticleState> c =
      initial_particles(scene_of(replaced(fill, "count: 200", "count: 200\n      seed: 5")));
  int same = 0;
  for (std::size_t i = 0; i < a.size(); ++i) same += same_bits(a[i], c[i]);
  EXPECT_EQ(same, 0);
}

// The fill tried one candidate at a time, written here apart from random_fill_particles: the
// k-th centre from the fill's seed, kept when is_free says so (then added), orientations from
// the second generator in the order the particles are kept.
std::vector<ParticleState> one_at_a_time(const Scene& scene, const RandomFillRequest& fill,
                                         std::vector<ParticleState> particles) {
  const double radius = scene.templates[fill.template_index].bounding_radius;
  const CentreSampler sampler(fill.region, radius);
  PlacementGrid grid(sampler.low(), sampler.high(), radius, particles.size() + fill.count);
  for (const ParticleState& p : particles) grid.add_sphere(p.position, bounding_radius(scene, p));
  for (const WallMesh& wall : make_wall_meshes(scene)) grid.add_mesh(wall.mesh);
  PlacementRandom centres(fill.seed), turns(fill_orientation_seed(fill.seed));
  for (long long placed = 0; placed < fill.count;) {
    const Vec3d c = sampler.sample(centres);
    if (!grid.is_free(c)) continue;
    grid.add_sphere(c, radius);
    ParticleState p;
    p.template_index = fill.template_index;
    p.position = c;
    if (fill.random_orientation) p.orientation = turns.orientation();
    particles.push_back(p);
    ++placed;
  }
  return particles;
}

TEST(InitialParticles, BatchesOnThreadsPlaceTheOneAtATimeFill) {
  // Two fills after a lattice, among walls, dense enough (bounding spheres 0.21 and 0.24 of the
  // regions) that most candidates are refused and, with batches of hundreds, many are
  // refused only for a candidate kept earlier in their own batch: every thread count and batch
  // must give the one-at-a-time fill's bits.
  const Scene scene = scene_of(R"(particles:
  - lattice:
      template: grain
      region: {box: {min: [0, 0, 0], max: [0.04, 0.04, 0.02]}}
      spacing: [0.012, 0.012, 0.012]
  - random:
      template: ball
      region: {box: {min: [0, 0, 0], max: [0.04, 0.04, 0.04]}}
      count: 400
      random_orientation: true
  - random:
      template: grain
      region: {cylinder: {base: [0.1, 0, 0], radius: 0.03, height: 0.06}}
      count: 80
      random_orientation: true
walls:
  - plane: {point: [0.02, 0.02, 0.0], normal: [0, 0, 1], size: 0.05, material: glass}
  - drum: {center: [0.1, 0, 0.03], radius: 0.0305, length: 0.06, segments: 24, material: glass}
)");
  ASSERT_EQ(scene.random_fills.size(), 2u);
  std::vector<ParticleState> lattice = lattice_particles(scene.lattices.at(0));
  const std::vector<ParticleState> after_first =
      one_at_a_time(scene, scene.random_fills[0], lattice);
  const std::vector<ParticleState> expected =
      one_at_a_time(scene, scene.random_fills[1], after_first);
  ASSERT_EQ(expected.size(), lattice.size() + 400 + 80);
  const std::vector<WallMesh> walls = make_wall_meshes(scene);
  for (const FillWork work : {FillWork{1, 1}, FillWork{1, 64}, FillWork{2, 7}, FillWork{3, 500},
                              FillWork{4, 4096}, FillWork{}}) {
    std::vector<ParticleState> particles = lattice;
    for (const RandomFillRequest& fill : scene.random_fills)
      random_fill_particles(scene, fill, walls, particles, work);
    ASSERT_EQ(particles.size(), expected.size());
    int differ = 0;
    for (std::size_t i = 0; i < particles.size(); ++i)
      differ += !same_bits(particles[i], expected[i]);
    EXPECT_EQ(differ, 0) << work.threads << " threads, batches of " << work.batch;
  }
  expect_no_overlaps(scene, expected);
}

TEST(InitialParticles, AListHandedOnIsTakenOnceThenMadeAgain) {
  const Scene scene = scene_of(R"(particles:
  - random:
      template: grain
      region: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}}
      count: 50
)");
  const std::vector<ParticleState> made = initial_particles(scene);
  std::vector<ParticleState> marked = made;
  marked[7].position.x = 42;  // not what a fill places: shows which list came back
  keep_initial_particles(scene, marked);
  const Scene copy = scene;  // the solver is built from a copy
  EXPECT_EQ(initial_particles(copy).at(7).position.x, 42);
  EXPECT_TRUE(same_bits(initial_particles(scene).at(7), made[7]));  // taken: made again
  // A list whose count is not the scene's (a stale one) is not taken.
  keep_initial_particles(scene, std::vector<ParticleState>(made.begin(), made.begin() + 10));
  EXPECT_EQ(initial_particles(scene).size(), 50u);
  // A resumed run's scene has no initial particles, and takes none.
  keep_initial_particles(scene, marked);
  EXPECT_TRUE(initial_particles(without_initial_particles(scene)).empty());
}

TEST(InitialParticles, FirstDrawsOfTheGeneratorAreTheStandardOnes) {
  // The standard fixes mt19937_64: its 10000th output from the default seed 5489 is
  // 9981545732273789042 ([rand.predef]). Our doubles are its top 53 bits over 2^53.
  PlacementRandom standard(5489);
  for (int i = 0; i < 9999; ++i) standard.engine()();
  EXPECT_EQ(standard.engine()(), 9981545732273789042ull);
  PlacementRandom random(5489), raw(5489);
  for (int i = 0; i < 100; ++i) {
    const double u = random.uniform();
    EXPECT_EQ(u, double(raw.engine()() >> 11) / 9007199254740992.0);
    EXPECT_GE(u, 0);
    EXPECT_LT(u, 1);
  }
}

TEST(InitialParticles, OrientationsAreUniformOnSO3) {
  // For rotations uniform on SO(3), every entry of the matrix has mean 0 and mean square 1/3.
  // With N = 40000 samples the standard error of the mean of an entry is sqrt(1/3 / N) = 0.0029
  // and of its square's mean sqrt((1/5 - 1/9) / N) = 0.0015 (E[x^4] = 1/5 for a coordinate of a
  // unit vector): 5 sigma gives the tolerances 0.015 and 0.0075.
  PlacementRandom random(42);
  const int n = 40000;
  double mean[3][3] = {}, square[3][3] = {};
  for (int s = 0; s < n; ++s) {
    const Mat3<double> r = rotation_matrix(random.orientation());
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        mean[i][j] += r.m[i][j] / n;
        square[i][j] += r.m[i][j] * r.m[i][j] / n;
      }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(mean[i][j], 0, 0.015) << i << j;
      EXPECT_NEAR(square[i][j], 1.0 / 3, 0.0075) << i << j;
    }
}

TEST(InitialParticles, PlacementGridAgreesWithBruteForce) {
  // Random spheres of mixed radii and random triangles; every query answered by the grid must
  // equal the exhaustive answer (the grid only prunes).
  PlacementRandom random(3);
  const double radius = 0.01;
  const Vec3d low(0, 0, 0), high(0.2, 0.1, 0.15);
  PlacementGrid grid(low, high, radius, 300);
  std::vector<Vec3d> centres;
  std::vector<double> radii;
  for (int i = 0; i < 300; ++i) {
    // Some spheres lie outside the box, and some are large: both must still be seen.
    centres.push_back(
        {random.uniform(-0.05, 0.25), random.uniform(-0.05, 0.15), random.uniform(-0.05, 0.2)});
    radii.push_back(i % 10 == 0 ? 0.05 : random.uniform(0.001, 0.01));
    grid.add_sphere(centres.back(), radii.back());
  }
  std::vector<Vec3d> triangles;
  for (int i = 0; i < 60; ++i) {
    const Vec3d a(random.uniform(-0.1, 0.3), random.uniform(-0.1, 0.2), random.uniform(-0.1, 0.25));
    const double size = i % 6 == 0 ? 0.3 : 0.02;
    const Vec3d b =
        a + Vec3d(random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1)) * size;
    const Vec3d c =
        a + Vec3d(random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1)) * size;
    triangles.insert(triangles.end(), {a, b, c});
    grid.add_triangle(a, b, c);
  }
  int free = 0;
  for (int q = 0; q < 20000; ++q) {
    const Vec3d p(random.uniform(low.x, high.x), random.uniform(low.y, high.y),
                  random.uniform(low.z, high.z));
    bool brute = true;
    for (std::size_t i = 0; i < centres.size(); ++i)
      if (norm2(p - centres[i]) < (radius + radii[i]) * (radius + radii[i])) brute = false;
    for (std::size_t t = 0; t < triangles.size(); t += 3)
      if (point_triangle_distance2(p, triangles[t], triangles[t + 1], triangles[t + 2]) <
          radius * radius)
        brute = false;
    ASSERT_EQ(grid.is_free(p), brute) << "query " << q;
    free += brute;
  }
  // Both answers occur often enough for the comparison to mean something.
  EXPECT_GT(free, 1000);
  EXPECT_LT(free, 19000);
}

TEST(InitialParticles, PlacementGridOnAFineFloorAgreesWithBruteForce) {
  // A floor meshed finer than the spheres (20,000 triangles, so the triangle cells are sized by
  // the mesh, not the default 32^3) and 600 equal spheres, each listed once in its
  // centre's cell: queries near the floor and among the spheres must match the exhaustive answer.
  PlacementRandom random(5);
  const double radius = 0.01;
  const Vec3d low(0, 0, 0), high(0.5, 0.5, 0.06);
  PlacementGrid grid(low, high, radius, 600);
  TriangleMesh floor;
  const int n = 100;  // 100 x 100 squares, two triangles each, 5 mm wide, 1 mm below z = 0
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) floor.vertices.push_back({0.5 * i / n, 0.5 * j / n, -0.001});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      floor.triangles.push_back({a, a + 1, a + n + 2});
      floor.triangles.push_back({a, a + n + 2, a + n + 1});
    }
  grid.add_mesh(floor);
  std::vector<Vec3d> centres;
  for (int i = 0; i < 600; ++i) {
    centres.push_back({random.uniform(0, 0.5), random.uniform(0, 0.5), random.uniform(0, 0.06)});
    grid.add_sphere(centres.back(), radius);
  }
  int free = 0, near_floor = 0;
  for (int q = 0; q < 4000; ++q) {
    const Vec3d p(random.uniform(0, 0.5), random.uniform(0, 0.5), random.uniform(0, 0.06));
    bool brute = true;
    for (const Vec3d& c : centres)
      if (norm2(p - c) < (2 * radius) * (2 * radius)) brute = false;
    bool touches_floor = false;
    for (const auto& t : floor.triangles)
      if (point_triangle_distance2(p, floor.vertices[t[0]], floor.vertices[t[1]],
                                   floor.vertices[t[2]]) < radius * radius)
        touches_floor = true;
    ASSERT_EQ(grid.is_free(p), brute && !touches_floor) << "query " << q;
    free += brute && !touches_floor;
    near_floor += touches_floor;
  }
  // Each kind of answer occurs often enough to mean something: about 1/6 of the queries lie
  // within 9 mm of the floor, and the spheres' excluded volumes (radius 2 cm, overlapping at
  // random) sum to 1.3 times the box's, so e^-1.3 = 0.27 of it stays free: about 900 answers.
  EXPECT_GT(near_floor, 300);
  EXPECT_GT(free, 300);
  EXPECT_LT(free, 2000);
}

TEST(InitialParticles, PointTriangleDistanceInEveryRegion) {
  const Vec3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Face, the three edges and the three vertices: distances by hand.
  EXPECT_DOUBLE_EQ(point_triangle_distance2({0.2, 0.2, 0.5}, a, b, c), 0.25);
  EXPECT_DOUBLE_EQ(point_triangle_distance2({0.5, -1, 0}, a, b, c), 1);
  EXPECT_DOUBLE_EQ(point_triangle_distance2({-2, 0.5, 0}, a, b, c), 4);
  EXPECT_DOUBLE_EQ(point_triangle_distance2({1, 1, 0}, a, b, c), 0.5);  // to (0.5, 0.5, 0)
  EXPECT_DOUBLE_EQ(point_triangle_distance2({-1, -1, 1}, a, b, c), 3);
  EXPECT_DOUBLE_EQ(point_triangle_distance2({3, -1, 0}, a, b, c), 5);
  EXPECT_DOUBLE_EQ(point_triangle_distance2({-1, 3, 0}, a, b, c), 5);
}

TEST(InitialParticles, AFillThatCannotBePlacedNamesItsEntryAndCount) {
  // A slab one diameter (and a bit) thick, cut by a plane wall through its middle except for the
  // strip x < 0.02: centres fit only at x < 0.018, room for about ten balls, not 100.
  const Scene scene = scene_of(R"(particles:
  - random:
      template: ball
      region: {box: {min: [0, 0, 0], max: [0.5, 0.01, 0.00404]}}
      count: 100
walls:
  - plane: {point: [0.26, 0.005, 0.00202], normal: [0, 0, 1], size: 0.48, material: glass}
)");
  try {
    initial_particles(scene);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("fill.yaml:12:7: particles[0].random: placed ", 0), 0u) << message;
    const long long placed = std::stoll(message.substr(message.find("placed ") + 7));
    EXPECT_GT(placed, 0);
    EXPECT_LT(placed, 100);
    EXPECT_NE(message.find(" of 100 particles of template 'ball'"), std::string::npos) << message;
  }
}

TEST(InitialParticles, HundredThousandSpheresFillQuickly) {
  // 1e5 balls of radius 2 mm at a sphere fraction of 0.2 in a cylinder with a drum around it
  // (random sequential addition slows sharply towards its jamming fraction 0.38: at 0.3 the
  // same fill takes far longer, most of it in the last fifth; benchmarks/history/README.md).
  const Scene scene = scene_of(R"(particles:
  - random:
      template: ball
      region: {cylinder: {base: [0, 0, 0], radius: 0.1, height: 0.5333}}
      count: 100000
walls:
  - drum: {center: [0, 0, 0.27], radius: 0.101, length: 0.54, segments: 96, material: glass}
)");
  const auto begin = std::chrono::steady_clock::now();
  const std::vector<ParticleState> particles = initial_particles(scene);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  RecordProperty("fill_seconds", std::to_string(seconds));
  std::printf("random fill of 1e5 spheres: %.3f s\n", seconds);
  ASSERT_EQ(particles.size(), 100000u);
  // Spot check against brute force: the last 200 placed against all the others.
  expect_no_overlaps(scene, particles, particles.size() - 200);
}

}  // namespace
}  // namespace talus
