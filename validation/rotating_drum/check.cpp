// Method paper §3.4 (Table 3, Fig. 15): a quasi-2D drum of dodecahedra turning at 45 rpm, filmed
// through its end plate. talus draws the frames (talus render's drawing, shaded as a camera sees
// them) at the paper's sampling interval and resolution, finds and tracks the particles in those
// pictures with OpenCV (image_tracking.hpp), builds the velocity field on a grid and compares it
// with the same field from the DEM's own velocities (drum_analysis.hpp): the paper's simulation
// met its experiment at R^2 = 0.8; the pictures must meet the DEM at R^2 >= 0.9. The dynamic
// angle of repose and the highest lift come from both. README.md here says what is run and why.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "solver/io/output_files.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "validation/framework/validation.hpp"
#include "validation/rotating_drum/drum_analysis.hpp"

#if TALUS_HAVE_OPENCV
#include "solver/io/vtk_output.hpp"
#include "solver/render/frame_drawing.hpp"
#include "solver/render/frame_image.hpp"
#include "validation/rotating_drum/image_tracking.hpp"
#endif

namespace talus::validation {
namespace {

// Table 3 and §3.4: 1 cm dodecahedra (circumscribed), a drum 1.1 cm thick, 45 rpm, frames every
// 5e-4 s at 960 x 960; §3.2's material with mu = 0.7.
constexpr double kSize = 0.01;        // m, circumscribed diameter
constexpr double kThickness = 0.011;  // m
constexpr double kRpm = 45;
constexpr double kSampling = 5e-4;   // s between frames
constexpr int kPixels = 960;         // the frames' width and height
constexpr double kSpacing = 0.0105;  // m between lattice points at the start
// s: 0.45 of the advisor's critical step for this material and size (the note says it)
constexpr double kStep = 2.5e-5;
// A regular dodecahedron's inradius over its circumradius (1.1135 a over 1.4013 a for edge a):
// half the narrowest width of its image is at least this times the circumradius.
constexpr double kInradiusRatio = 0.7947;

struct Drum {
  double radius;   // m
  int lattice;     // particles per side of the starting square lattice
  double spin_up;  // s before the first frame: the flow settles into its steady pattern
  double record;   // s of frames
  int cells;       // velocity grid: cells across the drum's diameter
};

std::string scene_text(const Drum& d) {
  const double half = 0.5 * d.lattice * kSpacing + 0.25 * kSpacing;  // lattice: n points fit
  return fmt::format(
      "# Method paper section 3.4: a quasi-2D drum {} m across and {} m thick, turning at\n"
      "# {} rpm, holding {} dodecahedra of {} mm. Written by\n"
      "# validation/rotating_drum/check.cpp (talus validate).\n"
      "time: {{step: {}, end: {}}}\n"
      "seed: 34\n\n"
      "materials:\n"
      "  resin: {{density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.7,\n"
      "          restitution: 0.1}}\n\n"
      "templates:\n"
      "  dodecahedron: {{shape: \"dodecahedron:{}\", material: resin}}\n\n"
      "particles:\n"
      "  - lattice:\n"
      "      template: dodecahedron\n"
      "      region: {{box: {{min: [{}, {}, {}], max: [{}, {}, {}]}}}}\n"
      "      spacing: [{}, {}, {}]\n"
      "      random_orientation: true\n"
      "      seed: 7\n\n"
      "walls:\n"
      "  - drum: {{name: drum, center: [0, 0, 0], axis: [0, 1, 0], radius: {}, length: {},\n"
      "            segments: 128, material: resin,\n"
      "            motion: {{rotation: {{axis: [0, 1, 0], point: [0, 0, 0], rpm: {}}}}}}}\n\n"
      "effects:\n"
      "  gravity: [0, 0, -9.81]\n"
      "  contact: volume\n"
      "  friction: true\n"
      "  rotation: true\n",
      2 * d.radius, kThickness, kRpm, d.lattice * d.lattice, kSize * 1e3, kStep,
      d.spin_up + d.record, kSize, -half, -kThickness / 2, -half, half, kThickness / 2, half,
      kSpacing, kThickness, kSpacing, d.radius, kThickness, kRpm);
}

#if TALUS_HAVE_OPENCV

// Per-frame measures of one source (the DEM's centres, or the pictures'), averaged at the end.
struct Measures {
  double repose_sum = 0, lift_sum = 0;
  int repose_frames = 0, lift_frames = 0;
  void add(const std::vector<PlanePoint>& centres, double radius, bool rising_right) {
    const double angle = repose_angle(centres, kSize, 0.5 * radius, 1.2 * kSize);
    if (std::isfinite(angle)) repose_sum += angle, ++repose_frames;
    const double lift = highest_lift(centres, radius, kSize, rising_right);
    if (lift > -90) lift_sum += lift, ++lift_frames;
  }
  double repose() const { return repose_frames ? repose_sum / repose_frames : std::nan(""); }
  double lift() const { return lift_frames ? lift_sum / lift_frames : std::nan(""); }
};

void run_case(const CaseContext& context, CaseResult& result) {
  // Small (CI, host): a drum half the size, 81 particles, 0.05 s of frames; full: the paper's
  // 0.3 m drum with 361 particles, 0.5 s of frames after 1.5 s (1.1 turns) of spinning up.
  const Drum drum = context.full ? Drum{0.15, 19, 1.5, 0.5, 20} : Drum{0.075, 9, 0.5, 0.05, 10};
  const std::string path = joined_path(context.output_directory, "scene.yaml");
  write_file_atomically(path, scene_text(drum));
  const Scene scene = load_case_scene(path, result);
  std::unique_ptr<AnyStep> step = context.make_step(scene);

  // The camera looks along the drum's axis (+y); the frame fits the drum with 16 px to spare.
  const ViewAxes axes = view_axes("y");
  const std::vector<WallMesh> meshes = make_wall_meshes(scene);
  const Projection projection =
      fit_projection(axes, meshes.at(0).mesh.vertices, kPixels, kPixels, 16);
  const double ppm = projection.pixels_per_metre;
  std::vector<TemplateSurface> surfaces;
  for (const ParticleTemplate& t : scene.templates) surfaces.push_back(template_surface(t));
  const auto to_plane = [&](double column, double row) {
    return PlanePoint{(column - projection.origin_column) / ppm,
                      (projection.origin_row - row) / ppm};
  };
  // The side whose wall rises: counter-clockwise in the picture when the drum's angular
  // velocity points at the camera, and then the right side goes up.
  const WallMotion& motion = scene.walls.at(0).motion;
  const Vec3d omega = motion.axis * motion.angular_speed();
  const bool rising_right = dot(omega, axes.toward_viewer) > 0;

  DetectionSettings detection;
  detection.inradius = kInradiusRatio * 0.5 * kSize * ppm;
  const std::string frames = joined_path(context.output_directory, "frames");
  create_output_directory(frames, "frame directory");

  const long long frame_every = std::llround(kSampling / kStep);
  const long long first = std::llround(drum.spin_up / kStep);
  const int frame_count = static_cast<int>(std::llround(drum.record / kSampling)) + 1;
  for (long long s = 0; s < first; ++s) step->step();

  VelocityField image_field(drum.cells, 2 * drum.radius / drum.cells);
  VelocityField dem_field(drum.cells, 2 * drum.radius / drum.cells);
  Measures dem, image;
  long long visible = 0, found = 0, matched = 0, detections = 0, links = 0;
  std::vector<double> errors;  // px between a matched detection and its particle's centre
  std::vector<PlanePoint> previous;
  std::string kept_csv = "frame,column,row,pixels\n";
  // `normal`: each face shaded by the light, as a camera sees it, with the particles' occluding
  // contours (`talus render --outline`): the bed is 1.1 particles thick, so particles overlap in
  // the picture, and one colour on another has no edge a camera would not also show darker.
  DrawSettings draw;
  draw.outline = true;
  for (int f = 0; f < frame_count; ++f) {
    if (f > 0)
      for (long long s = 0; s < frame_every; ++s) step->step();
    const double time = step->time();
    const std::vector<TrajectoryRow> rows = step->rows();
    const FrameDrawing drawing =
        draw_frame(projection, surfaces, rows, walls_at(scene, meshes, time), draw);
    const FrameImage picture = render_frame_image(drawing, kPixels, kPixels, rows.size(), "");
    const std::string png = joined_path(frames, fmt::format("frame_{:05d}.png", f));
    write_file_atomically(png, picture.png);

    // The DEM's truth: each centre in the picture's plane, its velocity there.
    std::vector<PlanePoint> truth, truth_visible;
    // A particle in full view shows about the 90th percentile of the visible areas (the
    // projected area varies by 15 % with the orientation; most of the bed hides a little).
    const std::vector<long long>& seen = picture.visible_pixels;
    std::vector<long long> sorted_seen(seen);
    const std::size_t high = sorted_seen.size() * 9 / 10;
    std::nth_element(sorted_seen.begin(), sorted_seen.begin() + high, sorted_seen.end());
    const long long typical = sorted_seen[high];
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const PixelPoint p = projection.project(rows[k].position);
      const PlanePoint at = to_plane(p.column, p.row);
      truth.push_back(at);
      dem_field.add(at, dot(axes.right, rows[k].velocity), dot(axes.up, rows[k].velocity));
      // More than half hidden behind nearer ones: not required to be found.
      if (2 * seen[k] >= typical) truth_visible.push_back(at);
    }
    dem.add(truth, drum.radius, rising_right);

    // The pictures: particles found, matched with the truth (scoring only), tracked frame to
    // frame by their nearest neighbour (the velocity field).
    std::vector<PlanePoint> centres;
    for (const ImageDetection& d : detect_particles(png, detection)) {
      centres.push_back(to_plane(d.column, d.row));
      if (f + 1 == frame_count)
        kept_csv += fmt::format("{},{:.3f},{:.3f},{}\n", f, d.column, d.row, d.pixels);
    }
    image.add(centres, drum.radius, rising_right);
    visible += static_cast<long long>(truth_visible.size());
    detections += static_cast<long long>(centres.size());
    const auto scored = match_nearest(centres, truth, 0.35 * kSize);
    for (const auto& [k, m] : scored) {
      const double a = std::hypot(centres[k].a - truth[m].a, centres[k].b - truth[m].b);
      errors.push_back(a * ppm);
    }
    matched += static_cast<long long>(scored.size());
    found += static_cast<long long>(match_nearest(truth_visible, centres, 0.35 * kSize).size());
    if (f > 0)
      for (const auto& [k, m] : match_nearest(previous, centres, 0.5 * kSize)) {
        const PlanePoint mid{0.5 * (previous[k].a + centres[m].a),
                             0.5 * (previous[k].b + centres[m].b)};
        image_field.add(mid, (centres[m].a - previous[k].a) / kSampling,
                        (centres[m].b - previous[k].b) / kSampling);
        ++links;
      }
    previous = centres;
    if (f != 0 && f + 1 != frame_count) std::filesystem::remove(png);  // keep the first, last
  }
  write_file_atomically(joined_path(context.output_directory, "detections.csv"), kept_csv);

  // The velocity fields, for the figure; R^2 over the cells with at least 20 samples (particle
  // frames) in each field: a cell's mean averages 20 particle-frames at least.
  constexpr int kMinSamples = 20;
  std::string fields = "a,b,u_image,w_image,n_image,u_dem,w_dem,n_dem\n";
  for (int j = 0; j < drum.cells; ++j)
    for (int i = 0; i < drum.cells; ++i) {
      const PlanePoint c = dem_field.centre(i, j);
      fields +=
          fmt::format("{:.6f},{:.6f},{:.6g},{:.6g},{},{:.6g},{:.6g},{}\n", c.a, c.b,
                      image_field.mean_u(i, j), image_field.mean_w(i, j), image_field.count(i, j),
                      dem_field.mean_u(i, j), dem_field.mean_w(i, j), dem_field.count(i, j));
    }
  write_file_atomically(joined_path(context.output_directory, "fields.csv"), fields);
  int cells_used = 0;
  const double r2 = field_r_squared(image_field, dem_field, kMinSamples, &cells_used);

  std::sort(errors.begin(), errors.end());
  const double median_error = errors.empty() ? std::nan("") : errors[errors.size() / 2];
  const double diameter_px = kSize * ppm;
  const Expected& e = context.expected;
  add_check(result, e.quantity("detection_recall"), 0,
            visible ? double(found) / double(visible) : 0, 1, "pictures vs DEM");
  add_check(result, e.quantity("detection_precision"), 0,
            detections ? double(matched) / double(detections) : 0, 1, "pictures vs DEM");
  add_check(result, e.quantity("centroid_error"), 0, median_error / diameter_px, 0,
            "pictures vs DEM");
  add_check(result, e.quantity("velocity_r2"), 0, r2, 1, "pictures vs DEM");
  add_check(result, e.quantity("repose_angle"), 0, image.repose(), dem.repose(), "pictures vs DEM");
  add_check(result, e.quantity("highest_lift"), 0, image.lift(), dem.lift(), "pictures vs DEM");
  add_check(result, e.quantity("repose_angle_dem"), 0, dem.repose(), 0, "DEM");
  add_check(result, e.quantity("highest_lift_dem"), 0, dem.lift(), 0, "DEM");
  result.notes.push_back(fmt::format(
      "{} dodecahedra in a drum {} m across on the {} backend, dt {} s: {} s of spinning up, "
      "then {} frames of {} x {} px every {} s ({:.1f} px per particle diameter); {} particles "
      "seen (at least half the area of one in full view), {} found, {} detections of which {} lie "
      "on a "
      "particle; median centroid error {:.2f} px; {} frame-to-frame links; R^2 {:.4f} over {} "
      "cells of {:.1f} mm; angle of repose {:.1f} deg (pictures {:.1f}), highest lift {:.1f} deg "
      "(pictures {:.1f}); frames {}, {} kept in frames/",
      step->particles(), 2 * drum.radius, context.backend, kStep, drum.spin_up, frame_count,
      kPixels, kPixels, kSampling, diameter_px, visible, found, detections, matched, median_error,
      links, r2, cells_used, 2e3 * drum.radius / drum.cells, dem.repose(), image.repose(),
      dem.lift(), image.lift(), frame_count, "the first and last"));
}

#else

void run_case(const CaseContext&, CaseResult&) {
  throw std::runtime_error(
      "this talus was built without OpenCV (Debian's libopencv-dev), which draws and reads the "
      "drum's pictures; scripts/setup installs it");
}

#endif

}  // namespace

extern const ValidationCase kRotatingDrum{
    "rotating_drum",
    "Quasi-2D rotating drum, tracked in pictures (method paper section 3.4, Fig. 15)",
    {"detection_recall", "detection_precision", "centroid_error", "velocity_r2", "repose_angle",
     "highest_lift", "repose_angle_dem", "highest_lift_dem"},
    run_case};

}  // namespace talus::validation
