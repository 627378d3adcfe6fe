// The `talus` commands that inspect shapes and contacts. Each returns its whole JSON document as a
// string (nothing is printed until it is complete) and throws UsageError for bad arguments.
#pragma once

#include <string>

namespace talus {

// `talus overlap A POSE_A B POSE_B`: the exact overlap of two posed polyhedra (paper §2.3), the
// simple contact of BLAZE-DEM (§2.3) and the GJK verdict (paper Algorithm I), side by side.
std::string overlap_json(const std::string& spec_a, const std::string& pose_a,
                         const std::string& spec_b, const std::string& pose_b);

// `talus shape A`: the template built from a spec (paper §2.1) in its body frame.
std::string shape_json(const std::string& spec);

}  // namespace talus
