// The `talus` command line. Results go to stdout as one JSON document; errors go to stderr as one
// line naming the offending argument, followed by the usage, with exit status 2.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "solver/app/arguments.hpp"
#include "solver/app/commands.hpp"
#include "solver/scene/scene_loader.hpp"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitFailure = 1;

const char* const kUsage =
    "usage:\n"
    "  talus                                  the built-in scene (as 'talus run')\n"
    "  talus run [options] [SCENE.yaml]       run a scene (docs/scenes.md); summary as JSON.\n"
    "                                         No scene: 63 dodecahedra poured into a 10 cm\n"
    "                                         cylinder (paper section 3.3), outputs in\n"
    "                                         talus-default/, its final bed height and picture\n"
    "  talus run --resume DIR [options]       continue a run from its last checkpoint\n"
    "  talus render [options] DIR             draw a run's frames to PNG (DIR: its trajectory\n"
    "                                         directory, with run.json)\n"
    "  talus overlap A POSE_A B POSE_B        overlap of two posed polyhedra, as JSON\n"
    "  talus shape A                          a shape template in its body frame, as JSON\n"
    "  talus help | --help | -h               this text\n"
    "\n"
    "A, B     a built-in shape 'name:size' or an .obj/.stl file ('path' or 'path:scale')\n"
    "         name: tetrahedron, cube, octahedron, dodecahedron, icosahedron, corn, mineral\n"
    "               (size = circumscribed-sphere diameter, m); cuboid:a,b,c (sides, m);\n"
    "               cylinder:D,L[,N] (diameter, length, N sides; m)\n"
    "POSE     x,y,z,qw,qx,qy,qz: centroid position (m) and orientation quaternion\n"
    "         (body -> world, normalised by talus), e.g. 0,0,0,1,0,0,0\n"
    "\n"
    "overlap prints: status, volume (m^3), normal (S/|S|, from A to B), area (|S|, m^2),\n"
    "vector_area (S), point (overlap centroid), chebyshev_depth (inradius of the overlap),\n"
    "depth, simple_normal, simple_point (BLAZE-DEM simple contact), gjk_intersecting.\n"
    "\n"
    "run options:\n"
    "  --solver production|reference   which solver steps the scene (default production;\n"
    "                                  reference: the serial CGAL/Eigen oracle)\n"
    "  --backend auto|cpu|cuda         overrides the scene's backend\n"
    "  --precision double|float        overrides the scene's precision\n"
    "  --output DIR                    relative output paths of the scene go inside DIR\n"
    "  --threads N                     the host backend's threads (N >= 1; default: all\n"
    "                                  cores, or OMP_NUM_THREADS)\n"
    "  --end T                         stop at T seconds instead of the scene's end time\n"
    "  --resume DIR                    continue the run from the newest checkpoint in DIR\n"
    "                                  (outputs.checkpoint) instead of a scene file; takes\n"
    "                                  --backend, --threads, --quiet and\n"
    "                                  --allow-unstable-step only\n"
    "  --quiet                         no progress lines on stderr\n"
    "  --allow-unstable-step           run a time step above the critical step that talus\n"
    "                                  estimates (refused otherwise; docs/contact.md)\n"
    "\n"
    "render options (pictures, their projection and each particle's pixel position go to\n"
    "DIR/render/ unless --output says otherwise; docs/scenes.md, \"Pictures\"):\n"
    "  --view x|-x|y|-y|z|-z           the direction the camera looks along (default y)\n"
    "  --color normal|velocity|id      faces shaded by normal, speed colours, or one flat\n"
    "                                  colour per particle id (default normal)\n"
    "  --width N, --height N           image size in pixels (default 800 x 800)\n"
    "  --every K                       every K-th frame (the last always); --last: only it\n"
    "  --fit all|particles             scale to fit particles and walls (default) or\n"
    "                                  particles only\n"
    "  --max-speed V                   m/s drawn red with --color velocity (default: the\n"
    "                                  fastest particle of the frames)\n"
    "  --scene FILE                    the scene, when run.json's path does not lead to it\n"
    "  --output DIR, --no-label, --quiet\n";

int usage_error(const std::string& message) {
  std::fprintf(stderr, "talus: error: %s\n\n%s", message.c_str(), kUsage);
  return kExitUsage;
}

int run(const std::vector<std::string>& args) {
  if (args.empty()) {
    std::fprintf(stderr,
                 "talus: no command given: 'talus run' ('talus --help' lists the "
                 "commands)\n");
    std::fputs(talus::run_json(talus::RunArguments{}).c_str(), stdout);
    return 0;
  }
  const std::string& command = args[0];
  const std::size_t operands = args.size() - 1;
  if (command == "help" || command == "--help" || command == "-h") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  std::string json;
  if (command == "overlap") {
    if (operands != 4) {
      return usage_error("overlap expects 4 arguments A POSE_A B POSE_B, got " +
                         std::to_string(operands));
    }
    json = talus::overlap_json(args[1], args[2], args[3], args[4]);
  } else if (command == "shape") {
    if (operands != 1) {
      return usage_error("shape expects 1 argument A, got " + std::to_string(operands));
    }
    json = talus::shape_json(args[1]);
  } else if (command == "run") {
    json = talus::run_json(
        talus::parse_run_arguments(std::vector<std::string>(args.begin() + 1, args.end())));
  } else if (command == "render") {
    json = talus::render_json(
        talus::parse_render_arguments(std::vector<std::string>(args.begin() + 1, args.end())));
  } else {
    return usage_error("unknown command '" + command +
                       "'; expected run, render, overlap, shape or help");
  }
  std::fputs(json.c_str(), stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    const int status = run(args);
    if (std::fflush(stdout) != 0) {
      std::fprintf(stderr, "talus: error: could not write the output\n");
      return kExitFailure;
    }
    return status;
  } catch (const talus::UsageError& error) {
    return usage_error(error.what());
  } catch (const talus::SceneError& error) {
    std::fprintf(stderr, "talus: error: %s\n", error.what());
    return kExitUsage;
  } catch (const talus::RunInterrupted& error) {
    std::fprintf(stderr, "talus: %s\n", error.what());
    return 128 + error.signal();
  } catch (const talus::RunError& error) {
    std::fprintf(stderr, "talus: error: %s\n", error.what());
    return kExitUsage;
  } catch (const std::exception& error) {
    // Not the user's arguments: an internal failure (e.g. out of memory).
    std::fprintf(stderr, "talus: error: %s\n", error.what());
    return kExitFailure;
  }
}
