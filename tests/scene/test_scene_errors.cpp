// Each class of scene error: the message names the file, the line and column, the key and what
// was expected. The scenes are kValidScene (scene_test_util.hpp) with one edit each, so every
// expected position below can be read off its text.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <utility>

#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

TEST(SceneErrors, TheUneditedSceneLoads) {
  const Scene scene = parse_scene(kValidScene, "errors.yaml", scene_data_dir());
  EXPECT_EQ(scene.materials.at(0).density, 2500);
  EXPECT_EQ(scene.particles.size(), 1u);
}

TEST(SceneErrors, WrongTypeNamesFileLineKeyAndExpectation) {
  const SceneError e = error_with("density: 2500", "density: abc");
  EXPECT_STREQ(e.what(),
               "errors.yaml:5:14: materials.glass.density: expected a positive number in kg/m^3, "
               "got 'abc'");
  EXPECT_EQ(e.file(), "errors.yaml");
  EXPECT_EQ(e.line(), 5);
  EXPECT_EQ(e.column(), 14);  // the value, after "    density: "
  EXPECT_EQ(e.key(), "materials.glass.density");
  EXPECT_EQ(e.message(), "expected a positive number in kg/m^3, got 'abc'");

  EXPECT_STREQ(error_with("position: [0, 0, 0.05]", "position: [0, zero, 0.05]").what(),
               "errors.yaml:16:37: particles[0].explicit[0].position: expected a position "
               "[x, y, z] in m, got [0, zero, 0.05]");
  EXPECT_STREQ(error_with("  - explicit:\n      - {template: grain, position: [0, 0, 0.05]}",
                          "  explicit: {template: grain}")
                   .what(),
               "errors.yaml:15:3: particles: expected a list of particle entries ({explicit: "
               "[...]}, {lattice: ...}, {random: ...}, {feed: ...}), got a map");
  EXPECT_STREQ(error_with("friction: true", "friction: maybe").what(),
               "errors.yaml:20:13: effects.friction: expected true or false, got 'maybe'");
  EXPECT_STREQ(error_with("seed: 3", "seed: [3]").what(),
               "errors.yaml:2:7: seed: expected a non-negative integer, got [3]");
  EXPECT_STREQ(error_with("seed: 3", "seed:").what(),  // a null value points at its key
               "errors.yaml:2:1: seed: expected a non-negative integer, got nothing");
}

TEST(SceneErrors, MissingRequiredKeyPointsAtItsMap) {
  // The glass map now starts at youngs_modulus, line 5.
  EXPECT_STREQ(error_with("    density: 2500\n", "").what(),
               "errors.yaml:5:5: materials.glass.density: missing required key; expected a "
               "positive number in kg/m^3");
  EXPECT_STREQ(error_with("templates:\n  grain:\n    shape: dodecahedron:0.01\n    material: "
                          "glass\n",
                          "")
                   .what(),
               "errors.yaml:1:1: templates: missing required key; expected a map from template "
               "names to shapes and materials");
  EXPECT_STREQ(error_with("{template: grain, position: [0, 0, 0.05]}", "{template: grain}").what(),
               "errors.yaml:16:9: particles[0].explicit[0].position: missing required key; "
               "expected a position [x, y, z] in m");
}

TEST(SceneErrors, UnknownKeyListsTheAllowedKeysAndTheLikelyOne) {
  EXPECT_STREQ(error_with("    density: 2500", "    densty: 2500").what(),
               "errors.yaml:5:5: materials.glass.densty: unknown key; expected one of density, "
               "youngs_modulus, poisson_ratio, friction, restitution (did you mean 'density'?)");
  EXPECT_STREQ(error_with("seed: 3", "sed: 3").what(),
               "errors.yaml:2:1: sed: unknown key; expected one of time, seed, backend, precision, "
               "skin, deterministic, reorder, domain, materials, material_pairs, templates, "
               "particles, walls, "
               "effects, outputs, decomposition (did you mean 'seed'?)");
  EXPECT_STREQ(error_with("seed: 3", "seed: 3\nseed: 4").what(),
               "errors.yaml:3:1: seed: duplicate key; first given on line 2");
}

struct RangeCase {
  std::string from, to, message;
};

TEST(SceneErrors, OutOfRangeValuesSayTheRange) {
  const std::vector<RangeCase> cases = {
      {"density: 2500", "density: -2500",
       "errors.yaml:5:14: materials.glass.density: expected a positive number in kg/m^3, got "
       "'-2500'"},
      {"density: 2500", "density: .inf",
       "errors.yaml:5:14: materials.glass.density: expected a positive number in kg/m^3, got "
       "'.inf' (infinite)"},
      {"youngs_modulus: 6.0e7", "youngs_modulus: 0",
       "errors.yaml:6:21: materials.glass.youngs_modulus: expected a positive number in Pa "
       "(Young's modulus), got '0'"},
      {"poisson_ratio: 0.23", "poisson_ratio: 0.5",
       "errors.yaml:7:20: materials.glass.poisson_ratio: expected a number in [0, 0.5) (Poisson's "
       "ratio), got '0.5'"},
      {"poisson_ratio: 0.23", "poisson_ratio: -0.1",
       "errors.yaml:7:20: materials.glass.poisson_ratio: expected a number in [0, 0.5) (Poisson's "
       "ratio), got '-0.1'"},
      {"friction: 0.4", "friction: -0.1",
       "errors.yaml:8:15: materials.glass.friction: expected a non-negative number (Coulomb "
       "friction coefficient), got '-0.1'"},
      {"restitution: 0.8", "restitution: 0",
       "errors.yaml:9:18: materials.glass.restitution: expected a number in (0, 1] (coefficient "
       "of restitution), got '0'"},
      {"restitution: 0.8", "restitution: 1.01",
       "errors.yaml:9:18: materials.glass.restitution: expected a number in (0, 1] (coefficient "
       "of restitution), got '1.01'"},
      {"seed: 3", "seed: 3\nskin: -1e-3",
       "errors.yaml:3:7: skin: expected a non-negative number in m, got '-1e-3'"},
      {"seed: 3", "seed: 3\ndeterministic: maybe",
       "errors.yaml:3:16: deterministic: expected true or false, got 'maybe'"},
      {"step: 1.0e-5", "step: 0",
       "errors.yaml:1:14: time.step: expected a positive number in s, or auto, got '0'"},
      {"step: 1.0e-5", "step: autp",
       "errors.yaml:1:14: time.step: expected a positive number in s, or auto, got 'autp'"},
      {"end: 0.1", "end: -1",
       "errors.yaml:1:27: time.end: expected a positive number in s, got '-1'"},
      {"step: 1.0e-5", "step: 1.0",
       "errors.yaml:1:14: time.step: expected a time step in s no longer than the end time, got "
       "'1.0'"},
  };
  for (const RangeCase& c : cases) {
    SCOPED_TRACE(c.to);
    EXPECT_EQ(error_with(c.from, c.to).what(), c.message);
  }
}

TEST(SceneErrors, UnknownMaterialOrTemplateListsTheDefinedOnes) {
  EXPECT_STREQ(error_with("material: glass", "material: glas").what(),
               "errors.yaml:13:15: templates.grain.material: unknown material 'glas'; defined: "
               "glass (did you mean 'glass'?)");
  EXPECT_STREQ(error_with("{template: grain,", "{template: sand,").what(),
               "errors.yaml:16:20: particles[0].explicit[0].template: unknown template 'sand'; "
               "defined: grain");
}

TEST(SceneErrors, UnknownShapeWrapsTheShapeMessage) {
  const SceneError unknown = error_with("dodecahedron:0.01", "dodecahedrn:0.01");
  EXPECT_EQ(unknown.key(), "templates.grain.shape");
  EXPECT_EQ(unknown.line(), 12);
  EXPECT_EQ(unknown.column(), 12);
  EXPECT_EQ(unknown.message().rfind("shape spec 'dodecahedrn:0.01': unknown shape 'dodecahedrn'; "
                                    "expected one of ",
                                    0),
            0u)
      << unknown.what();
  const SceneError size = error_with("dodecahedron:0.01", "dodecahedron:-0.01");
  EXPECT_EQ(size.message().rfind("shape spec 'dodecahedron:-0.01': dodecahedron needs one "
                                 "positive size D",
                                 0),
            0u)
      << size.what();
}

TEST(SceneErrors, UnknownEffectOrContactModel) {
  EXPECT_STREQ(error_with("  friction: true", "  friction: true\n  magnetism: 1").what(),
               "errors.yaml:21:3: effects.magnetism: unknown effect; expected one of gravity, "
               "contact, friction, rotation, drag");
  EXPECT_STREQ(error_with("contact: volume", "contact: hertz").what(),
               "errors.yaml:19:12: effects.contact: expected a contact model, one of volume, "
               "volume_paper, linear, got 'hertz'");
  EXPECT_STREQ(error_with("contact: volume", "contact: {model: hertz}").what(),
               "errors.yaml:19:20: effects.contact.model: expected a contact model, one of "
               "volume, volume_paper, linear, got 'hertz'");
}

TEST(SceneErrors, MissingFilesAreNamed) {
  EXPECT_STREQ(error_with("shape: dodecahedron:0.01", "shape: grains/missing.stl").what(),
               ("errors.yaml:12:12: templates.grain.shape: mesh file '" + scene_data_dir() +
                "/grains/missing.stl' does not exist (relative paths start at the scene file's "
                "directory)")
                   .c_str());
  EXPECT_STREQ(error_with("effects:",
                          "walls:\n  - mesh: {file: tray.stl, material: glass}\n"
                          "effects:")
                   .what(),
               ("errors.yaml:18:18: walls[0].mesh.file: mesh file '" + scene_data_dir() +
                "/tray.stl' does not exist (relative paths start at the scene file's "
                "directory)")
                   .c_str());
  const std::string missing = scene_data_dir() + "/no_such_scene.yaml";
  try {
    load_scene(missing);
    ADD_FAILURE() << "no error for a missing scene file";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.what(), missing + ": the scene file does not exist");
    EXPECT_EQ(e.line(), 0);
  }
}

TEST(SceneErrors, ScenesAndMeshesThatAreNotRegularFilesAreNamedAsWhatTheyAre) {
  const std::string dir = testing::TempDir() + "talus_scene_specials_" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/folder.stl");
  const std::string fifo = dir + "/pipe.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A FIFO with no writer would block the load forever if it were opened; /dev/zero would be read
  // forever; a directory would read as an empty scene.
  for (const auto& [path, what] :
       {std::pair<std::string, std::string>{fifo, "is a FIFO (named pipe), not a regular file"},
        {dir + "/folder.stl", "is a directory, not a regular file"},
        {"/dev/zero", "is a character device, not a regular file"}}) {
    try {
      load_scene(path);
      ADD_FAILURE() << "loaded " << path;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.what(), path + ": the scene file " + what);
    }
  }
  // A mesh file given as a directory or a FIFO, at the key that names it.
  EXPECT_STREQ(error_with("shape: dodecahedron:0.01", "shape: " + dir + "/folder.stl").what(),
               ("errors.yaml:12:12: templates.grain.shape: mesh file '" + dir +
                "/folder.stl' is a directory, not a regular file (relative paths start at the "
                "scene file's directory)")
                   .c_str());
  const std::string fifo_mesh = dir + "/pipe.obj";
  ASSERT_EQ(::mkfifo(fifo_mesh.c_str(), 0600), 0);
  EXPECT_STREQ(error_with("shape: dodecahedron:0.01", "shape: " + fifo_mesh).what(),
               ("errors.yaml:12:12: templates.grain.shape: mesh file '" + fifo_mesh +
                "' is a FIFO (named pipe), not a regular file (relative paths start at the "
                "scene file's directory)")
                   .c_str());
  std::filesystem::remove_all(dir);
}

// A mesh wall's file that cannot be used: the message names the key, the wall, the file and (in a
// text file) its line; a generated wall with a corner beyond kMaxWallReach names the wall.
TEST(SceneErrors, WallMeshProblemsNameTheWallAndTheFile) {
  const std::string dir = testing::TempDir() + "talus_wall_meshes_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + "/" + name) << text;
    return dir + "/" + name;
  };
  const auto wall_error = [](const std::string& wall) {
    return std::string(error_with("effects:", "walls:\n  - " + wall + "\neffects:").what());
  };
  const std::string nan = write("nan.obj", "v 0 0 0\nv 1 nan 0\n");
  EXPECT_EQ(wall_error("mesh: {name: chute, file: " + nan + ", material: glass}"),
            "errors.yaml:18:31: walls[0].mesh.file: wall 'chute': " + nan +
                ":2: vertex y 'nan' is not a finite number; expected 'v x y z' with three numbers");
  const std::string line = write("line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  EXPECT_EQ(wall_error("mesh: {file: " + line + ", material: glass}"),
            "errors.yaml:18:18: walls[0].mesh.file: wall 'mesh_0': mesh file '" + line +
                "': its one triangle has zero area; a wall needs a surface");
  const std::string tetra = write("tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(wall_error("mesh: {name: big, file: " + tetra + ", scale: 1e300, material: glass}"),
            "errors.yaml:18:29: walls[0].mesh.file: wall 'big': mesh file '" + tetra +
                "': vertex 2, placed by scale, rotation and translation, lies 1e+300 m from the "
                "origin, beyond the largest distance talus supports, 1e+06 m");
  EXPECT_EQ(wall_error("box: {name: bin, min: [-1e300, 0, 0], max: [1, 1, 1], material: glass}"),
            "errors.yaml:18:10: walls[0].box: wall 'bin': a corner lies 1e+300 m from the origin, "
            "beyond the largest distance talus supports, 1e+06 m");
  std::filesystem::remove_all(dir);
}

TEST(SceneErrors, YamlSyntaxErrorsGiveThePosition) {
  // yaml-cpp finds an unclosed flow list at the next key (line 19); the message names the
  // bracket that is not closed, where it opens.
  const SceneError unclosed = error_with("gravity: [0, 0, -9.81]", "gravity: [0, 0, -9.81");
  EXPECT_EQ(unclosed.file(), "errors.yaml");
  EXPECT_EQ(unclosed.line(), 18);
  EXPECT_EQ(unclosed.key(), "");
  EXPECT_EQ(unclosed.message(), "invalid YAML: this '[' has no matching ']'") << unclosed.what();
  // A key indented under a scalar value.
  const SceneError indented = error_with("seed: 3", "seed: 3\n  extra: 4");
  EXPECT_EQ(indented.line(), 3);
  EXPECT_EQ(indented.message().rfind("invalid YAML: ", 0), 0u) << indented.what();
}

TEST(SceneErrors, EmptyOrNonMapDocument) {
  EXPECT_EQ(scene_error("").message(),
            "expected a scene: a map with keys time, seed, backend, precision, skin, "
            "deterministic, reorder, domain, materials, material_pairs, templates, particles, "
            "walls, effects, "
            "outputs, decomposition, got an empty file");
  EXPECT_STREQ(scene_error("- 1\n- 2\n").what(),
               "errors.yaml:1:1: expected a scene: a map with keys time, seed, backend, precision, "
               "skin, deterministic, reorder, domain, materials, material_pairs, templates, "
               "particles, walls, "
               "effects, outputs, decomposition, got [1, 2]");
}

}  // namespace
}  // namespace talus

namespace talus {
namespace {

// `domain:` (docs/scenes.md): a box above min on every axis, holding every explicit particle and
// every lattice, fill and feed region, or the error names the item and where the box was written.
TEST(SceneErrors, DomainBoxMustHoldWhatTheSceneStartsWith) {
  const std::string effects = "effects:\n";
  const Scene ok =
      parse_scene(replaced(kValidScene, effects,
                           "domain: {min: [-0.1, -0.1, 0], max: [0.1, 0.1, 0.2]}\n" + effects),
                  "errors.yaml", scene_data_dir());
  ASSERT_TRUE(ok.domain.has_value());
  EXPECT_EQ(ok.domain->max.z, 0.2);
  EXPECT_EQ(ok.domain_source.line, 17);

  EXPECT_STREQ(error_with(effects, "domain: {min: [0, 0, 0], max: [1, 0, 1]}\n" + effects).what(),
               "errors.yaml:17:31: domain.max: expected a corner above min on every axis, got "
               "[1, 0, 1]");
  EXPECT_STREQ(error_with(effects, "domain: {min: [0, 0, 0]}\n" + effects).what(),
               "errors.yaml:17:9: domain.max: missing required key; expected [x, y, z], the "
               "highest corner in m");
  // The particle at z = 0.05 lies above a box that ends at 0.04.
  const SceneError outside =
      error_with(effects, "domain: {min: [-0.1, -0.1, 0], max: [0.1, 0.1, 0.04]}\n" + effects);
  EXPECT_EQ(outside.line(), 16);
  EXPECT_EQ(outside.key(), "particles[0].explicit[0]");
  EXPECT_NE(std::string(outside.what()).find("outside the domain box written at errors.yaml:17"),
            std::string::npos)
      << outside.what();
  EXPECT_STREQ(error_with(effects, "reorder: maybe\n" + effects).what(),
               "errors.yaml:17:10: reorder: expected true or false, got 'maybe'");
}

// Outputs that would write over each other are refused where the scene names them (item 2 of
// "Runs that never lose data"): two outputs on one path (compared as written, after '.' and '..'
// and trailing slashes are resolved), a probe file named like a file of the output directory it
// lies in, or like the run lock. Outputs side by side are fine.
TEST(SceneErrors, OutputPathsThatCollideAreRefused) {
  const auto with_outputs = [](const std::string& outputs) {
    return kValidScene + "outputs:\n" + outputs;
  };
  const Scene ok = parse_scene(
      with_outputs(
          "  trajectories: {every: 10, directory: out/frames}\n"
          "  probes: {every: 1, file: out/frames/probes.csv, quantities: [kinetic_energy]}\n"
          "  vtk: {every: 10, directory: out/vtk}\n"
          "  checkpoint: {every: 10, directory: out/checkpoints}\n"),
      "errors.yaml", scene_data_dir());
  EXPECT_EQ(ok.outputs.probes->file, "out/frames/probes.csv");
  const struct {
    std::string outputs, message;
  } cases[] = {
      {"  trajectories: {every: 10, directory: out}\n  vtk: {every: 10, directory: ./out/}\n",
       "errors.yaml:23:31: outputs.vtk.directory: './out/' is also the path of "
       "outputs.trajectories; give each output a path of its own"},
      {"  probes: {every: 1, file: a/../runs, quantities: [kinetic_energy]}\n"
       "  checkpoint: {every: 5, directory: runs}\n",
       "errors.yaml:23:37: outputs.checkpoint.directory: 'runs' is also the path of "
       "outputs.probes; give each output a path of its own"},
      // The default directories collide too: the error points at the output's map.
      {"  trajectories: {every: 10}\n  vtk: {every: 10, directory: trajectories}\n",
       "errors.yaml:23:31: outputs.vtk.directory: 'trajectories' is also the path of "
       "outputs.trajectories; give each output a path of its own"},
      {"  trajectories: {every: 10, directory: out}\n"
       "  probes: {every: 1, file: out/run.json, quantities: [kinetic_energy]}\n",
       "errors.yaml:23:28: outputs.probes.file: 'out/run.json' lies in the directory of "
       "outputs.trajectories under a name that output writes; name the probe file another way"},
      {"  trajectories: {every: 10, directory: out}\n"
       "  probes: {every: 1, file: out/trajectory_000000010.csv, quantities: [kinetic_energy]}\n",
       "errors.yaml:23:28: outputs.probes.file: 'out/trajectory_000000010.csv' lies in the "
       "directory of outputs.trajectories under a name that output writes; name the probe file "
       "another way"},
      {"  checkpoint: {every: 10}\n"
       "  probes: {every: 1, file: checkpoints/checkpoint_000000001.bin, quantities: "
       "[kinetic_energy]}\n",
       "errors.yaml:23:28: outputs.probes.file: 'checkpoints/checkpoint_000000001.bin' lies in "
       "the directory of outputs.checkpoint under a name that output writes; name the probe "
       "file another way"},
      {"  vtk: {every: 10, directory: v}\n"
       "  probes: {every: 1, file: v/particles.pvd, quantities: [kinetic_energy]}\n",
       "errors.yaml:23:28: outputs.probes.file: 'v/particles.pvd' lies in the directory of "
       "outputs.vtk under a name that output writes; name the probe file another way"},
      {"  probes: {every: 1, file: ./.talus.lock, quantities: [kinetic_energy]}\n",
       "errors.yaml:22:28: outputs.probes.file: './.talus.lock' is the run lock's file; name the "
       "probe file another way"},
  };
  for (const auto& c : cases)
    EXPECT_STREQ(scene_error(with_outputs(c.outputs)).what(), c.message.c_str()) << c.outputs;
}

}  // namespace
}  // namespace talus
