// Where the pair and wall stages read the templates' BodyProperties (mass, inertia, radii, the
// shape's arrays): the "templates in constant memory with a fallback for large sets". In
// the CUDA step, when a region of the constant bank is free and the scene's templates fit in it,
// they are copied there (cuda_step.cu) and `constant_region` names it: every thread of a warp
// whose pairs share a template then reads the same address, which the constant cache
// broadcasts, and the reads leave the L1 cache to the overlap workspaces. Otherwise, and always
// on the host, they are read through `bodies`. The shape's vertex and face arrays stay in global
// memory: different threads read different vertices, which the constant cache would serialise.
#pragma once

#include <vector>

#include "solver/core/hd.hpp"
#include "solver/step/particle_kernels.hpp"

namespace talus {

// The constant bank's share for templates: kTemplateRegions regions of kTemplateRegionBytes,
// one per CudaStep alive at a time (a step that finds none free reads global memory).
constexpr int kTemplateRegions = 4;
constexpr int kTemplateRegionBytes = 8 * 1024;  // 40 templates in double

#if defined(__CUDACC__)
namespace template_table_detail {
// Raw bytes: a __constant__ object may not have a constructor, which BodyProperties has. Internal
// linkage (no relocatable device code): each CUDA translation unit has its own copy, which
// that unit must fill for its kernels (fill_template_region).
static __constant__ __align__(
    16) unsigned char constant_templates[kTemplateRegions * kTemplateRegionBytes];
}  // namespace template_table_detail
#endif

template <class Real>
struct TemplateTable {
  const BodyProperties<Real>* bodies = nullptr;  // per template (device or host memory)
  int constant_region = -1;                      // the same templates in constant memory; -1: no

  TemplateTable() = default;
  TemplateTable(const BodyProperties<Real>* b) : bodies(b) {}  // NOLINT: a table is its array

  // By value: a reference would merge the two address spaces into one generic pointer, whose
  // loads bypass the constant cache; a copy made in each branch keeps ld.const in the constant
  // one (after inlining only the fields a caller uses are loaded).
  TALUS_HD BodyProperties<Real> operator[](int template_id) const {
#if defined(__CUDA_ARCH__)
    if (constant_region >= 0) {
      return reinterpret_cast<const BodyProperties<Real>*>(
          template_table_detail::constant_templates +
          constant_region * kTemplateRegionBytes)[template_id];
    }
#endif
    return bodies[template_id];
  }
};

// How many templates of type Real one region holds.
template <class Real>
constexpr int templates_per_region() {
  return kTemplateRegionBytes / static_cast<int>(sizeof(BodyProperties<Real>));
}

#if defined(__CUDACC__)
}  // namespace talus

#include "solver/core/cuda_check.hpp"

namespace talus {

// Copies the templates (device views) into region `region` of the calling translation unit's
// constant bank. Static, like the bank: each unit whose kernels read a TemplateTable calls it
// (the pair stage and the wall stage of the CUDA step).
template <class Real>
static void fill_template_region(const std::vector<BodyProperties<Real>>& bodies, int region) {
  TALUS_CUDA_CHECK(cudaMemcpyToSymbol(template_table_detail::constant_templates, bodies.data(),
                                      bodies.size() * sizeof(BodyProperties<Real>),
                                      static_cast<std::size_t>(region) * kTemplateRegionBytes));
}
#endif

}  // namespace talus
