#include "solver/contact/time_step_advisor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "solver/contact/contact_laws.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_loader.hpp"

namespace talus {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Area of a merged face from its vertex loop (planar polygon: half the cross products' sum,
// along the face's normal).
double face_area(const ShapeTemplate& shape, const Face& face) {
  Vec3d twice;
  const std::size_t n = face.loop.size();
  for (std::size_t i = 0; i < n; ++i)
    twice += cross(shape.vertices[face.loop[i]], shape.vertices[face.loop[(i + 1) % n]]);
  return 0.5 * std::abs(dot(twice, face.normal));
}

// How many particles of each template the scene can hold at once, saturated at 2: a template
// contacts itself only when two of its particles can exist. A lattice counts as its points
// (initial_particles.cpp's count); a feed as many.
std::vector<int> template_counts(const Scene& scene) {
  std::vector<long long> count(scene.templates.size(), 0);
  for (const ParticleState& p : scene.particles) ++count[p.template_index];
  for (const LatticeRequest& lattice : scene.lattices) {
    const double points = lattice_point_count(lattice.region, lattice.spacing);
    count[lattice.template_index] += points >= 2 ? 2 : 1;
  }
  for (const RandomFillRequest& fill : scene.random_fills)
    count[fill.template_index] += std::min(fill.count, 2LL);
  for (const FeedRequest& feed : scene.feeds) count[feed.template_index] += 2;
  std::vector<int> saturated(count.size());
  for (std::size_t i = 0; i < count.size(); ++i) saturated[i] = int(std::min(count[i], 2LL));
  return saturated;
}

// The largest initial speed of the scene's particles (explicit, lattices, fills, feeds), m/s.
double largest_initial_speed(const Scene& scene) {
  double speed = 0;
  for (const ParticleState& p : scene.particles) speed = std::max(speed, norm(p.velocity));
  for (const LatticeRequest& l : scene.lattices) speed = std::max(speed, norm(l.velocity));
  for (const RandomFillRequest& f : scene.random_fills) speed = std::max(speed, norm(f.velocity));
  for (const FeedRequest& f : scene.feeds) speed = std::max(speed, norm(f.velocity));
  return speed;
}

// Eqs. 15 and 20 as a damping ratio: c = 2 zeta sqrt(k m_eff), zeta = -ln eps / sqrt(ln^2 eps +
// pi^2) (the ratio that makes a linear spring-dashpot rebound with eps).
double restitution_damping_ratio(double restitution) {
  const double log_e = std::log(restitution);
  return -log_e / std::sqrt(log_e * log_e + M_PI * M_PI);
}

// One mode of a contact: a spring k and a dashpot c acting along a direction on which the bodies'
// inverse masses add to w (1/kg). Its equation q'' + c w q' + k w q = 0 has omega = sqrt(k w)
// and the damping ratio zeta = c w / (2 omega). talus's velocity Verlet takes the force at the
// Euler-predicted velocity v* = v + a dt (dynamics/integrator.hpp), and on this oscillator its
// amplification matrix has the eigenvalue -1 at omega dt = 2 (sqrt(1 + 4 zeta^2) - 2 zeta)
// (det(A + I) = 4 - h^2 - 8 zeta h, h = omega dt), its first exit from the unit circle: the
// classical limit 2 (sqrt(1 + zeta^2) - zeta) of a damper at the mid-step velocity, with zeta
// doubled (a dashpot alone, k -> 0: c w dt <= 1). tests/contact/test_time_step_advisor.cpp runs
// the integrator on both sides of it.
struct Mode {
  double stiffness = 0, inverse_mass = 0, omega = 0, damping_ratio = 0, critical_step = kInfinity;
};

Mode oscillator(double stiffness, double zeta, double inverse_mass) {
  Mode mode;
  mode.stiffness = stiffness;
  mode.inverse_mass = inverse_mass;
  if (stiffness <= 0) return mode;
  mode.omega = std::sqrt(stiffness * inverse_mass);
  mode.damping_ratio = zeta;
  mode.critical_step = 2 / mode.omega * (std::sqrt(1 + 4 * zeta * zeta) - 2 * zeta);
  return mode;
}

}  // namespace

TemplateProperties template_properties(const Scene& scene, int template_index) {
  const ParticleTemplate& t = scene.templates.at(template_index);
  const Material& material = scene.materials.at(t.material);
  TemplateProperties p;
  p.youngs_modulus = material.youngs_modulus;
  p.poisson_ratio = material.poisson_ratio;
  p.density = material.density;
  if (t.kind == ParticleShapeKind::sphere) {
    const double r = t.sphere_radius;
    p.mass = material.density * 4.0 / 3.0 * M_PI * r * r * r;
    p.smallest_moment = 0.4 * p.mass * r * r;
    p.bounding_radius = r;
    p.equivalent_radius = r;
    p.largest_face_area = M_PI * r * r;  // the disc a flat contact could at most reach
    return p;
  }
  const ShapeTemplate& shape = t.shape;
  p.mass = material.density * shape.volume;
  p.smallest_moment = material.density * shape.principal_moments.x;  // ascending, per density
  p.bounding_radius = shape.bounding_radius;
  p.equivalent_radius = std::cbrt(3 * shape.volume / (4 * M_PI));
  for (const Face& face : shape.faces)
    p.largest_face_area = std::max(p.largest_face_area, face_area(shape, face));
  return p;
}

double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio) {
  const double shear_modulus = youngs_modulus / (2 * (1 + poisson_ratio));
  return M_PI * radius * std::sqrt(density / shear_modulus) / (0.1631 * poisson_ratio + 0.8766);
}

std::string TimeStepAdvice::describe() const {
  return limited() ? limit + ", contact: " + model : limit;
}

double round_down_two_digits(double value) {
  if (!std::isfinite(value) || value <= 0) return value;
  const int exponent = int(std::floor(std::log10(value))) - 1;
  // Two digits m in [10, 99] with m 10^exponent <= value, read back from their decimal text so
  // that the number printed with %.1e is the double returned.
  auto decimal = [exponent](long long m) {
    return std::stod(std::to_string(m) + "e" + std::to_string(exponent));
  };
  long long digits = (long long)(std::floor(value / std::pow(10.0, exponent)));
  while (digits < 99 && decimal(digits + 1) <= value) ++digits;
  while (digits > 1 && decimal(digits) > value) --digits;
  return decimal(digits);
}

TimeStepAdvice advise_time_step(const Scene& scene) {
  TimeStepAdvice advice;
  advice.critical_step = kInfinity;
  advice.recommended_step = kInfinity;
  advice.rayleigh_time = kInfinity;

  const std::vector<int> counts = template_counts(scene);
  std::vector<int> present;
  std::vector<TemplateProperties> props(scene.templates.size());
  for (std::size_t i = 0; i < scene.templates.size(); ++i) {
    if (counts[i] == 0) continue;
    present.push_back(int(i));
    props[i] = template_properties(scene, int(i));
    const TemplateProperties& p = props[i];
    advice.rayleigh_time =
        std::min(advice.rayleigh_time,
                 rayleigh_time(p.equivalent_radius, p.density, p.youngs_modulus, p.poisson_ratio));
  }

  const Effects& effects = scene.effects;
  if (!effects.contact) {
    advice.limit = "no contacts (effects.contact is absent)";
    return advice;
  }
  const ContactModel model = *effects.contact;
  advice.model = to_string(model);
  if (present.empty()) {
    advice.limit = "no particles";
    return advice;
  }
  const double gravity = effects.gravity ? norm(*effects.gravity) : 0.0;
  const double speed = largest_initial_speed(scene);
  const bool at_load =
      with_contact_law(model, [](auto law) { return decltype(law)::kStiffnessAtLoad; });
  if (at_load && gravity == 0 && speed == 0) {
    advice.limit = std::string("no load: the ") + to_string(model) +
                   " law's stiffness is unbounded as the overlap vanishes and is evaluated at "
                   "the load a contact carries, and the scene has neither gravity nor an "
                   "initial speed";
    return advice;
  }

  // One contact kind: template a against template b, or against wall w (b = -1). A wall is
  // rigid: it adds nothing to K or G (Eqs. 13, 19) and has infinite mass.
  auto add_kind = [&](int a, int b, int w) {
    const TemplateProperties& pa = props[a];
    const TemplateProperties* pb = b >= 0 ? &props[b] : nullptr;
    ContactKindAdvice kind;
    kind.template_a = a;
    kind.template_b = b;
    kind.wall = w;
    kind.name = scene.templates[a].name + "-" +
                (pb ? scene.templates[b].name
                    : (scene.walls.size() == 1 ? std::string("wall")
                                               : "wall '" + scene.walls[w].name + "'"));
    const int material_b = pb ? scene.templates[b].material : scene.walls[w].material;
    const double restitution = scene.pair_restitution(scene.templates[a].material, material_b);

    // K = E_a/R_a + E_b/R_b and G = E_a/(2(1+nu_a)R_a) + ... (Eqs. 13 and 19 without A_n).
    double modulus = pa.youngs_modulus / pa.equivalent_radius;
    double shear = pa.youngs_modulus / (2 * (1 + pa.poisson_ratio) * pa.equivalent_radius);
    double radius_min = pa.equivalent_radius;
    // The stiffest contact is face on face; two bodies touch at most over the smaller of their
    // largest faces (at a wall: the particle's).
    double area = pa.largest_face_area;
    double mass_max = pa.mass;
    // Translational m_eff = (1/m_a + 1/m_b)^-1, the mass in Eqs. 15 and 20.
    double inverse_translational = 1 / pa.mass;
    if (pb) {
      modulus += pb->youngs_modulus / pb->equivalent_radius;
      shear += pb->youngs_modulus / (2 * (1 + pb->poisson_ratio) * pb->equivalent_radius);
      radius_min = std::min(radius_min, pb->equivalent_radius);
      area = std::min(area, pb->largest_face_area);
      mass_max = std::max(mass_max, pb->mass);
      inverse_translational += 1 / pb->mass;
    }

    // The law's k_n at the contact's stiffest state (contact/laws/), and its normal damping
    // ratio (below).
    StiffestContact stiffest;
    stiffest.modulus = modulus;
    stiffest.area = area;
    stiffest.radius_min = radius_min;
    stiffest.mass_max = mass_max;
    stiffest.inverse_mass = inverse_translational;
    stiffest.effective_mass = 1 / inverse_translational;
    stiffest.gravity = gravity;
    stiffest.speed = speed;
    stiffest.linear_stiffness = effects.linear.stiffness;
    stiffest.linear_damping = effects.linear.damping;
    bool tangential_spring = false;
    const AdvisedStiffness normal_stiffness = with_contact_law(model, [&](auto law) {
      tangential_spring = decltype(law)::kTangentialHistory;
      return decltype(law)::largest_normal_stiffness(stiffest);
    });
    kind.normal_stiffness = normal_stiffness.normal_stiffness;
    kind.load = normal_stiffness.load;
    // The tangential spring k_t = G A_n (Eq. 19) acts only with friction (Eq. 17); the linear
    // law has none (its tangential force is a capped dashpot, BLAZE-DEM Eq. 3).
    if (effects.friction && tangential_spring) kind.tangential_stiffness = shear * area;

    // The inverse mass along the contact with the worst lever arm: 1/m + R_b^2 / I_min per body
    // (a unit force at distance R_b, its torque about the axis of least inertia). A sphere's
    // normal force passes through its centre (the lens along the centre line, the nearest
    // facet's normal, pressure on a sphere is radial), so its normal mode has no rotation term;
    // its tangential force acts at the surface (R_b = r). Without the rotation effect bodies
    // only translate.
    // The stiffest normal contact is a whole face on a face (k_n above), whose point is the
    // face's centre: on the line of the centroid for the regular shapes, so that mode has no
    // rotation term; a patch off the centre is smaller, and k_n ~ A^2 falls faster than the
    // lever arm adds (a sphere's normal force passes through its centre anyway). The tangential
    // force acts in the contact plane: the worst lever arm, R_b.
    auto inverse_mass = [&](bool normal) {
      double w = 0;
      for (int t : {a, b}) {
        if (t < 0) continue;
        const TemplateProperties& p = props[t];
        w += 1 / p.mass;
        if (effects.rotation && !normal)
          w += p.bounding_radius * p.bounding_radius / p.smallest_moment;
      }
      return w;
    };
    // Damping ratios: the dashpots' own on m_eff, Eqs. 15 and 20's zeta(eps) for both volume
    // laws (volume_paper's calibrated c_n rebounds with the same eps), eta / (2 sqrt(k m_eff))
    // for the linear law. A mode with rotation meets its dashpot with a smaller mass, so a larger
    // ratio, but the worst lever arm taken for it is a bound, not a contact's: the two bounds
    // together would refuse the tetrahedra's 1e-5 s (7e-6 s), which they run at rest
    // (tests/step/test_hard_cases.cpp).
    const double zeta = restitution_damping_ratio(restitution);
    const double zeta_n = with_contact_law(model, [&](auto law) {
      return decltype(law)::normal_damping_ratio(stiffest, kind.normal_stiffness, zeta);
    });
    const Mode normal = oscillator(kind.normal_stiffness, zeta_n, inverse_mass(true));
    const Mode tangential = oscillator(kind.tangential_stiffness, zeta, inverse_mass(false));
    const Mode& limiting = tangential.critical_step < normal.critical_step ? tangential : normal;
    kind.stiffness = limiting.stiffness;
    kind.inverse_mass = limiting.inverse_mass;
    kind.omega = limiting.omega;
    kind.damping_ratio = limiting.damping_ratio;
    kind.critical_step = limiting.critical_step;
    advice.kinds.push_back(kind);
  };

  for (std::size_t i = 0; i < present.size(); ++i)
    for (std::size_t j = i; j < present.size(); ++j)
      if (i != j || counts[present[i]] >= 2) add_kind(present[i], present[j], -1);
  for (int a : present)
    for (std::size_t w = 0; w < scene.walls.size(); ++w) add_kind(a, -1, int(w));

  if (advice.kinds.empty()) {
    advice.limit = "no contact can occur (one particle and no walls)";
    return advice;
  }
  for (std::size_t k = 0; k < advice.kinds.size(); ++k)
    if (advice.limiting_kind < 0 ||
        advice.kinds[k].critical_step < advice.kinds[advice.limiting_kind].critical_step)
      advice.limiting_kind = int(k);
  const ContactKindAdvice& limiting = advice.kinds[advice.limiting_kind];
  advice.critical_step = limiting.critical_step;
  advice.limit = limiting.name + " contacts";
  // `step: auto` takes a fifth of dt_crit: dt_crit holds for one contact alone, and a particle
  // pressed by n neighbours at once has up to n times the stiffness (omega grows as sqrt(n), so
  // 0.2 leaves room for about 25 aligned contacts); it also gives at least pi / (0.4) = 8 steps
  // per half period of the contact's oscillation, the usual minimum to resolve a rebound.
  advice.recommended_step = kAutoStepFraction * advice.critical_step;
  return advice;
}

void refuse_unstable_step(const Scene& scene, const TimeStepAdvice& advice) {
  const double dt = scene.time_step;
  if (!(dt > advice.critical_step)) return;
  const double stable = round_down_two_digits(advice.critical_step);
  const SourceRef& at = scene.time_step_source;
  throw SceneError(at.file.empty() ? scene.file : at.file, at.line, at.column, "time.step",
                   fmt::format("{:.6g} s is above the largest stable step {:.1e} s for {} "
                               "(contact: {}); write time.step <= {:.1e} or step: auto, or pass "
                               "--allow-unstable-step to run anyway",
                               dt, stable, advice.limit, advice.model, stable));
}

}  // namespace talus
