// Checks across keys and sections: effects that need other effects, walls and outputs that need
// what they measure, requests that cannot be met, names given twice. Each case is kValidScene
// (scene_test_util.hpp) with edits, and the full message it must give.
#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

struct Edit {
  std::string from, to;
};
struct CheckCase {
  std::string name;
  std::vector<Edit> edits;
  std::string message;
};

const std::string kOneParticle = "  - explicit:\n      - {template: grain, position: [0, 0, 0.05]}";
const std::string kEffects =
    "effects:\n  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n";

void expect_message(const CheckCase& c) {
  SCOPED_TRACE(c.name);
  std::string text = kValidScene;
  for (const Edit& edit : c.edits) text = replaced(text, edit.from, edit.to);
  EXPECT_EQ(scene_error(text).what(), c.message) << text;
}

TEST(SceneChecks, EffectsNeedWhatTheyActThrough) {
  const std::vector<CheckCase> cases = {
      {"walls listed as an effect",
       {{"  friction: true", "  friction: true\n  walls: true"}},
       "errors.yaml:21:10: effects.walls: the walls effect follows from the walls list; leave it "
       "out of effects"},
      {"friction without contact",
       {{"  contact: volume\n", ""}},
       "errors.yaml:19:13: effects.friction: friction acts at contacts: the scene needs a contact "
       "model (effects.contact)"},
      {"linear model without parameters",
       {{"contact: volume", "contact: linear"}},
       "errors.yaml:19:12: effects.contact: the linear model needs its parameters: write {model: "
       "linear, stiffness: K_N, damping: eta, tangential_damping: gamma}"},
      {"linear model with friction but no tangential damping",
       {{"contact: volume", "contact: {model: linear, stiffness: 1.0e4, damping: 0.1}"}},
       "errors.yaml:19:12: effects.contact: the linear model with friction needs "
       "tangential_damping: a non-negative number in N s/m (gamma of BLAZE-DEM Eq. 3, the "
       "friction force's cap per unit tangential speed)"},
      {"volume model with a stiffness",
       {{"contact: volume", "contact: {model: volume, stiffness: 1}"}},
       "errors.yaml:19:39: effects.contact.stiffness: the volume model takes its stiffness and "
       "damping from the materials (paper Eqs. 13, 15, 19, 20); only the linear model has this "
       "key"},
      {"walls without a contact model",
       {{kEffects,
         "walls:\n  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 1, material: "
         "glass}\neffects:\n  gravity: [0, 0, -9.81]\n"}},
       "errors.yaml:18:3: walls: walls act through contacts, and the scene has no contact model "
       "(effects.contact)"},
  };
  for (const CheckCase& c : cases) expect_message(c);
}

TEST(SceneChecks, WallsAreCheckedAgainstTheirKind) {
  const std::string hopper =
      "walls:\n  - hopper:\n      base: [0, 0, 0]\n      top_radius: 0.05\n      bottom_radius: "
      "BOTTOM\n      height: 0.1\n      material: glass\n";
  const std::vector<CheckCase> cases = {
      {"unknown wall kind",
       {{"effects:", "walls:\n  - cone: {radius: 1, material: glass}\neffects:"}},
       "errors.yaml:18:5: walls[0].cone: unknown wall kind; expected one of mesh, plane, box, "
       "cylinder, drum, hopper, silo"},
      {"hopper outlet as wide as its top",
       {{"effects:", hopper + "effects:"}, {"BOTTOM", "0.05"}},
       "errors.yaml:21:22: walls[0].hopper.bottom_radius: expected a positive number in m below "
       "top_radius (the outlet), got '0.05'"},
      {"opening time of an open outlet",
       {{"effects:", hopper + "      outlet_opens_at: 0.5\neffects:"}, {"BOTTOM", "0.01"}},
       "errors.yaml:24:24: walls[0].hopper.outlet_opens_at: outlet_opens_at applies to a closed "
       "outlet; add 'outlet: closed'"},
      {"a wall name used twice",
       {{"effects:",
         "walls:\n  - plane: {name: floor, point: [0, 0, 0], normal: [0, 0, 1], size: 1, material: "
         "glass}\n  - plane: {name: floor, point: [0, 0, 1], normal: [0, 0, -1], size: 1, "
         "material: glass}\neffects:"}},
       "errors.yaml:19:19: walls[1].plane.name: wall name 'floor' is already used by "
       "walls[0].plane"},
      {"a zero normal",
       {{"effects:",
         "walls:\n  - plane: {point: [0, 0, 0], normal: [0, 0, 0], size: 1, material: "
         "glass}\neffects:"}},
       "errors.yaml:18:39: walls[0].plane.normal: expected a normal, a nonzero vector [x, y, z], "
       "got [0, 0, 0]"},
  };
  for (const CheckCase& c : cases) expect_message(c);
}

TEST(SceneChecks, ParticleRequestsThatCannotBeMet) {
  const std::string random =
      "  - random:\n      template: grain\n      region: {box: {min: [0, 0, 0], max: [0.1, 0.1, "
      "0.1]}}\n";
  const std::vector<CheckCase> cases = {
      {"lattice spacing below the bounding diameter",
       {{kOneParticle,
         "  - lattice:\n      template: grain\n      region: {box: {min: [0, 0, 0], "
         "max: [0.1, 0.1, 0.1]}}\n      spacing: 0.008"}},
       "errors.yaml:18:16: particles[0].lattice.spacing: expected a spacing in m, one number or "
       "[x, y, z], each at least the bounding diameter 0.01 m of template 'grain' so that "
       "particles do not overlap, got '0.008'"},
      {"random fill denser than random placement reaches",
       // 800 bounding spheres of radius 5 mm in a litre: 800 * 5.236e-7 m^3 / 1e-3 m^3 = 0.419.
       {{kOneParticle, random + "      count: 800"}},
       "errors.yaml:18:14: particles[0].random.count: 800 particles of template 'grain' need "
       "bounding spheres filling 0.419 of the region; random placement jams near 0.38: ask for "
       "fewer or a larger region"},
      {"random fill with both a count and a fraction",
       {{kOneParticle, random + "      count: 10\n      volume_fraction: 0.1"}},
       "errors.yaml:16:7: particles[0].random: expected either count (a number of particles) or "
       "volume_fraction (particle volume over region volume), got both"},
      {"a region smaller than one particle",
       {{kOneParticle,
         "  - random:\n      template: grain\n      region: {cylinder: {base: [0, 0, "
         "0], radius: 0.001, height: 1}}\n      count: 1"}},
       "errors.yaml:17:15: particles[0].random.region: expected a region that holds one bounding "
       "sphere of template 'grain' (diameter 0.01 m)"},
      {"a box whose max is below its min",
       {{kOneParticle,
         "  - random:\n      template: grain\n      region: {box: {min: [0, 0, 0], "
         "max: [0.1, -0.1, 0.1]}}\n      count: 1"}},
       "errors.yaml:17:43: particles[0].random.region.box.max: expected a corner [x, y, z] in m "
       "above min on every axis, got [0.1, -0.1, 0.1]"},
      {"a feed that starts after the end",
       {{kOneParticle,
         "  - feed:\n      template: grain\n      region: {box: {min: [0, 0, 0], "
         "max: [0.1, 0.1, 0.1]}}\n      rate: 10\n      start: 0.2"}},
       "errors.yaml:19:14: particles[0].feed.start: expected a non-negative number in s, before "
       "the end time, got '0.2'"},
      {"a zero quaternion",
       {{"position: [0, 0, 0.05]}", "position: [0, 0, 0.05], orientation: [0, 0, 0, 0]}"}},
       "errors.yaml:16:64: particles[0].explicit[0].orientation: expected an orientation: a "
       "quaternion [w, x, y, z] or {axis: [x, y, z], degrees: angle}, got [0, 0, 0, 0] (a zero "
       "quaternion is no rotation)"},
  };
  for (const CheckCase& c : cases) expect_message(c);
}

TEST(SceneChecks, OutputsNeedWhatTheyMeasure) {
  const std::vector<CheckCase> cases = {
      {"bed height without gravity",
       {{"  gravity: [0, 0, -9.81]\n", ""},
        {"  friction: true",
         "  friction: true\noutputs:\n  probes: {every: 10, quantities: [kinetic_energy, "
         "bed_height]}"}},
       "errors.yaml:21:52: outputs.probes.quantities[1]: bed_height is measured against gravity; "
       "the scene has no effects.gravity"},
      {"wall forces without walls",
       {{"  friction: true",
         "  friction: true\noutputs:\n  probes: {every: 10, quantities: "
         "[wall_forces]}"}},
       "errors.yaml:22:36: outputs.probes.quantities[0]: wall_forces needs walls; the scene has "
       "none"},
      {"output every zero steps",
       {{"  friction: true", "  friction: true\noutputs:\n  trajectories: {every: 0}"}},
       "errors.yaml:22:25: outputs.trajectories.every: expected a positive integer number of "
       "steps, got '0'"},
      {"output every fractional step",
       {{"  friction: true", "  friction: true\noutputs:\n  trajectories: {every: 2.5}"}},
       "errors.yaml:22:25: outputs.trajectories.every: expected a positive integer number of "
       "steps, got '2.5'"},
      {"vtk output every zero steps",
       {{"  friction: true", "  friction: true\noutputs:\n  vtk: {every: 0}"}},
       "errors.yaml:22:16: outputs.vtk.every: expected a positive integer number of steps, got "
       "'0'"},
      {"vtk output without every",
       {{"  friction: true", "  friction: true\noutputs:\n  vtk: {directory: pv}"}},
       "errors.yaml:22:8: outputs.vtk.every: missing required key; expected a positive integer "
       "number of steps"},
      {"an unknown particle form",
       {{"  friction: true", "  friction: true\noutputs:\n  vtk: {every: 5, particles: meshes}"}},
       "errors.yaml:22:30: outputs.vtk.particles: expected a particle form, one of surfaces, "
       "points, got 'meshes'"},
      {"a misspelt vtk key",
       {{"  friction: true", "  friction: true\noutputs:\n  vtk: {every: 5, particle: points}"}},
       "errors.yaml:22:19: outputs.vtk.particle: unknown key; expected one of every, directory, "
       "particles (did you mean 'particles'?)"},
      {"the trajectory format that VTK output replaced",
       {{"  friction: true",
         "  friction: true\noutputs:\n  trajectories: {every: 5, format: vtk}"}},
       "errors.yaml:22:36: outputs.trajectories.format: trajectories are CSV or HDF5 files; "
       "for ParaView's VTK files write outputs.vtk"},
      {"an unknown trajectory format",
       {{"  friction: true", "  friction: true\noutputs:\n  trajectories: {every: 5, format: h5}"}},
       "errors.yaml:22:36: outputs.trajectories.format: expected a trajectory format, one of "
       "csv, hdf5, got 'h5'"},
      {"checkpoints every zero steps",
       {{"  friction: true", "  friction: true\noutputs:\n  checkpoint: {every: 0}"}},
       "errors.yaml:22:23: outputs.checkpoint.every: expected a positive integer number of "
       "steps, got '0'"},
      {"checkpoints without every",
       {{"  friction: true", "  friction: true\noutputs:\n  checkpoint: {keep: 3}"}},
       "errors.yaml:22:15: outputs.checkpoint.every: missing required key; expected a positive "
       "integer number of steps"},
      {"keeping no checkpoint",
       {{"  friction: true", "  friction: true\noutputs:\n  checkpoint: {every: 5, keep: 0}"}},
       "errors.yaml:22:32: outputs.checkpoint.keep: expected a positive integer number of "
       "checkpoint files, got '0'"},
      {"a misspelt checkpoint key",
       {{"  friction: true", "  friction: true\noutputs:\n  checkpoint: {every: 5, dir: ck}"}},
       "errors.yaml:22:26: outputs.checkpoint.dir: unknown key; expected one of every, "
       "directory, keep"},
      {"an unknown output",
       {{"  friction: true", "  friction: true\noutputs:\n  restart: {every: 5}"}},
       "errors.yaml:22:3: outputs.restart: unknown key; expected one of trajectories, probes, "
       "vtk, checkpoint"},
  };
  for (const CheckCase& c : cases) expect_message(c);
}

TEST(SceneChecks, NamesAndChoices) {
  const std::vector<CheckCase> cases = {
      {"a template name given twice",
       {{"    material: glass\n",
         "    material: glass\n  grain: {sphere: 0.01, material: glass}\n"}},
       "errors.yaml:14:3: templates.grain: duplicate name; first given on line 11"},
      {"a scale for a built-in shape",
       {{"    material: glass", "    material: glass\n    scale: 0.001"}},
       "errors.yaml:14:12: templates.grain.scale: scale applies to mesh files only; a built-in "
       "shape's size is in its spec"},
      {"a pair with an unknown material",
       {{"templates:",
         "material_pairs:\n  - {materials: [glass, sand], friction: 0.2}\ntemplates:"}},
       "errors.yaml:11:25: material_pairs[0].materials[1]: unknown material 'sand'; defined: "
       "glass"},
      {"a pair that overrides nothing",
       {{"templates:", "material_pairs:\n  - {materials: [glass, glass]}\ntemplates:"}},
       "errors.yaml:11:5: material_pairs[0]: expected friction, restitution or both to override "
       "for this pair, got neither"},
      {"an unknown backend",
       {{"seed: 3", "seed: 3\nbackend: metal"}},
       "errors.yaml:3:10: backend: expected a backend, one of auto, cpu, cuda, got 'metal'"},
      {"a negative seed",
       {{"seed: 3", "seed: -1"}},
       "errors.yaml:2:7: seed: expected a non-negative integer, got '-1'"},
      {"a material name that is not a name",
       {{"  glass:", "  2glass:"}, {"material: glass", "material: 2glass"}},
       "errors.yaml:5:5: materials.2glass: expected a material name of letters, digits, '_' or "
       "'-', starting with a letter, got '2glass'"},
  };
  for (const CheckCase& c : cases) expect_message(c);
  // Both a shape and a sphere: the message offers the two.
  const SceneError both =
      error_with("    material: glass", "    material: glass\n    sphere: 0.01");
  EXPECT_EQ(both.line(), 12);
  EXPECT_EQ(both.key(), "templates.grain");
  EXPECT_EQ(both.message().rfind("expected either 'shape' (", 0), 0u) << both.what();
}

}  // namespace
}  // namespace talus
