// The contact laws' table: the ONE place where the scene's contact model (a runtime value, read
// from `effects.contact`) becomes a law type (contact/laws/: VolumeLaw, the default;
// VolumePaperLaw; LinearLaw). The host calls with_contact_law once per stage call (or once per
// setting up), and what it passes on is templated on the law: the pair and wall functions
// (step/pair_kernels.hpp, step/wall_kernels.hpp), the CUDA kernels and the history stores. Host
// code only. Adding a law: its file in contact/laws/, its case here (docs/ARCHITECTURE.md,
// "Extending talus", "A contact law").
#pragma once

#include "solver/contact/laws/linear_law.hpp"
#include "solver/contact/laws/volume_law.hpp"
#include "solver/contact/laws/volume_paper_law.hpp"
#include "solver/scene/scene.hpp"

namespace talus {

// f(Law{}) for the law of `model`; every law's call must return the same type.
template <class F>
decltype(auto) with_contact_law(ContactModel model, F&& f) {
  switch (model) {
    case ContactModel::volume:
      return f(VolumeLaw{});
    case ContactModel::volume_paper:
      return f(VolumePaperLaw{});
    case ContactModel::linear:
      break;
  }
  return f(LinearLaw{});
}

}  // namespace talus
