// Random placement of particles without overlap: reproducible random numbers, uniform points in
// a region and uniform orientations, and a grid that answers "is this bounding sphere free of
// the spheres and wall triangles placed so far?" in constant time.
//
// Reproducibility: the generator is std::mt19937_64, whose output the standard fixes; doubles
// come from its top 53 bits (not std::uniform_real_distribution, whose mapping differs between
// standard libraries), orientations by rejection in the 4-ball (only +, *, sqrt: no libm call
// whose last bit may differ), and the files that compute positions are compiled with
// -ffp-contract=off. The same request therefore gives the same bits on every machine.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

class PlacementRandom {
 public:
  explicit PlacementRandom(std::uint64_t seed) : engine_(seed) {}
  double uniform();                         // [0, 1), 53 random bits
  double uniform(double low, double high);  // [low, high)
  Quatd orientation();                      // uniform on SO(3), w >= 0
  std::mt19937_64& engine() { return engine_; }
  const std::mt19937_64& engine() const { return engine_; }

 private:
  std::mt19937_64 engine_;
};

// Where the centre of a sphere of `radius` may go so that the sphere lies inside `region`: a
// box shrunk by the radius, or a cylinder whose radius and height shrink by it.
class CentreSampler {
 public:
  CentreSampler(const Region& region, double radius);
  Vec3d sample(PlacementRandom& random) const;
  // The axis-aligned box that holds every point sample() can return.
  Vec3d low() const { return low_; }
  Vec3d high() const { return high_; }

 private:
  Region region_;
  double radius_;
  Vec3d u_, v_;  // cylinder: axis_basis(axis)
  Vec3d low_, high_;
};

// Squared distance from p to the closest point of triangle (a, b, c) (Ericson, Real-Time
// Collision Detection §5.1.5: Voronoi regions of the vertices, edges and face).
double point_triangle_distance2(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);

// Uniform cells over the box of admissible centres for spheres of one radius. A stored sphere
// that a new one can touch only within one cell's width (all of them when every radius is the
// grid's) is listed once, in its centre's cell, with its centre and squared reach beside it, and
// a query reads the 27 cells around its own; a wider one (a larger particle placed before) and
// each triangle is listed in every cell from which a new sphere could touch it. The cells grow
// with the expected count (a few per sphere) and the triangle cells with the triangles, so that a
// query reads about as many entries at ten million spheres as at a thousand. The exact tests
// decide; the grid only saves work, so the answers (and the particles placed) do not depend on
// the cell size.
class PlacementGrid {
 public:
  // `low`, `high`: the box of the centres to be queried; `radius`: the new spheres' radius;
  // `expected`: about how many spheres will be stored (sizes the grid).
  PlacementGrid(const Vec3d& low, const Vec3d& high, double radius, std::size_t expected);
  void add_sphere(const Vec3d& centre, double radius);
  void add_triangle(const Vec3d& a, const Vec3d& b, const Vec3d& c);
  // Adds every triangle of `mesh`; the first mesh added before any triangle sizes the triangle
  // cells for its count.
  void add_mesh(const TriangleMesh& mesh);
  // The triangles stored in `other`, a grid of the same box and radius, in place of this one's:
  // as if the meshes added there had been added here (a grid's triangles are kept apart from
  // its spheres). Throws std::invalid_argument for another box or radius.
  void take_triangles_of(const PlacementGrid& other);
  // True when a sphere of the grid's radius at `centre` (inside the box) overlaps no stored
  // sphere (distance of centres below the sum of radii) and no stored triangle (closer than the
  // radius). Touching is allowed.
  bool is_free(const Vec3d& centre) const;
  double radius() const { return radius_; }
  // Calls visit(a, b, c) for every stored triangle that may lie within the grid's radius of
  // `centre` (inside the box): a superset, which the caller narrows with the exact distance.
  template <class Visit>
  void for_each_triangle_near(const Vec3d& centre, Visit visit) const {
    for (int i = triangle_cells_.head[triangle_cells_.cell_of(centre)]; i >= 0;) {
      const auto [next, item] = triangle_cells_.node[i];
      const Vec3d* t = &triangle_vertices_[3 * std::size_t(item)];
      visit(t[0], t[1], t[2]);
      i = next;
    }
  }

 private:
  struct Cells {
    Vec3d low;
    double size = 1;
    int n[3] = {1, 1, 1};
    std::vector<int> head;                  // first node of each cell, -1 when empty
    std::vector<std::pair<int, int>> node;  // (next node, item)
    void init(const Vec3d& low, const Vec3d& high, double min_size, std::size_t max_cells);
    int coordinate(double x, int axis) const;
    int cell_of(const Vec3d& p) const;
    void add(int cell, int item);
  };
  struct Near {  // a sphere listed in its centre's cell
    Vec3d centre;
    double reach2;  // (grid radius + its radius)^2
    int next;
  };
  void init_triangle_cells(std::size_t triangles);
  double radius_;
  Vec3d low_, high_;
  Cells sphere_cells_;      // the cells; head: the first of each cell's `near_` spheres
  std::vector<Near> near_;  // spheres that reach at most one cell from their own
  Cells wide_cells_;        // the other spheres, in every cell they reach (head lazily)
  std::vector<Vec3d> wide_centres_;
  std::vector<double> wide_radii_;
  Cells triangle_cells_;
  std::vector<Vec3d> triangle_vertices_;  // three per triangle
};

// One particle of `template_index` placed at random: up to `attempts` centres drawn by `sampler`
// until one is free in `grid`; then the grid takes its sphere (of the grid's radius) and the
// particle gets a random orientation when asked, `velocity` and `source`. False when none of the
// attempts was free (the grid and `particle` are then unchanged).
bool place_one(const CentreSampler& sampler, PlacementGrid& grid, PlacementRandom& random,
               int attempts, int template_index, bool random_orientation, const Vec3d& velocity,
               const SourceRef& source, ParticleState& particle);

}  // namespace talus
