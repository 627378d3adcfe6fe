// The validation cases, in the order `talus validate` runs them: each defined in its folder's
// check.cpp.
#include "validation/framework/validation.hpp"

namespace talus::validation {

extern const ValidationCase kFreeFallDrag;
extern const ValidationCase kCylinderWallImpact;
extern const ValidationCase kDodecahedronPacking;
extern const ValidationCase kMeshResolution;
extern const ValidationCase kGravityPacking;
extern const ValidationCase kRotatingDrum;
extern const ValidationCase kHopperFlow;

const std::vector<ValidationCase>& validation_cases() {
  static const std::vector<ValidationCase> cases = {
      kFreeFallDrag, kCylinderWallImpact, kMeshResolution, kDodecahedronPacking,
      kRotatingDrum, kGravityPacking,     kHopperFlow};
  return cases;
}

}  // namespace talus::validation
