// Particles found in a picture as a camera would give it (method paper §3.4, Fig. 15a: the paper
// found them with Mask R-CNN; talus with OpenCV's classical tools): the pixels that show a
// particle, split into one segment per particle, and each segment's centroid. Built where
// OpenCV is found (with talus render); image_tracking.cpp is the one file here that uses it.
//
// What a pixel shows is read from its colour: talus render's `normal` colouring paints particles
// a light steel blue shaded by the light (blue exceeds red by 17 to 50 of 255 from the darkest
// face to the brightest), on white, with the walls' outline and the particles' occluding
// contours (`--outline`) in grey (blue equals red). A camera with coloured particles against a
// plain background gives the same contrast.
#pragma once

#include <string>
#include <vector>

namespace talus::validation {

struct ImageDetection {
  double column = 0, row = 0;  // the segment's centroid, px (pixel (c, r) centred at (c, r))
  long long pixels = 0;        // the segment's area
};

struct DetectionSettings {
  // px: half the narrowest width of one particle's image (a dodecahedron: its inradius times
  // the pixels per metre). The splitting of touching particles is scaled by it.
  double inradius = 12;
  // A pixel shows a particle when its blue exceeds its red by more than this (0-255).
  int min_blue_excess = 10;
};

// The particles in the PNG at `path`: the particle pixels (by colour, then opened by a 3 x 3
// square to drop one-pixel slivers), their distance to the nearest other pixel (distance
// transform), one seed per local maximum of that distance at least 0.4 `inradius` deep, none
// higher in the square of half-side 0.8 `inradius` about it and no seed within that distance
// (touching convex particles meet at a neck, each keeps its own maximum near its centre), each
// particle pixel given to its nearest seed, and each seed's pixels' centroid. Throws
// std::runtime_error naming the file when it cannot be read as an image.
std::vector<ImageDetection> detect_particles(const std::string& path,
                                             const DetectionSettings& settings);

}  // namespace talus::validation
