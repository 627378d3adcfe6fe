// The contact-law types (solver/contact/laws/) and their table (solver/contact/contact_laws.hpp):
// each scene model maps to the law of its name, the traits say what the kernels and stores do for
// it, and a pair's elastic part is a wall facet's of weight 1, to the bit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "solver/contact/contact_laws.hpp"

namespace talus {
namespace {

TEST(ContactLaws, TableMapsEachModelToTheLawOfItsName) {
  for (const ContactModel model :
       {ContactModel::volume, ContactModel::volume_paper, ContactModel::linear}) {
    const std::string name =
        with_contact_law(model, [](auto law) { return std::string(decltype(law)::kName); });
    EXPECT_EQ(name, to_string(model));
  }
}

TEST(ContactLaws, Traits) {
  static_assert(VolumeLaw::kVolumeGeometry && VolumeLaw::kTangentialHistory);
  static_assert(VolumeLaw::kPatchCouple && !VolumeLaw::kCalibratedDamping);
  static_assert(VolumePaperLaw::kVolumeGeometry && VolumePaperLaw::kTangentialHistory);
  static_assert(!VolumePaperLaw::kPatchCouple && VolumePaperLaw::kCalibratedDamping);
  static_assert(VolumePaperLaw::kStiffnessAtLoad && !VolumeLaw::kStiffnessAtLoad);
  static_assert(!LinearLaw::kVolumeGeometry && !LinearLaw::kTangentialHistory);
  static_assert(!LinearLaw::kPatchCouple && !LinearLaw::kStiffnessAtLoad);
  SUCCEED();
}

// Below and above the default law's switch volume A_ref^(3/2) (1.1e-7 m^3), and for the paper's
// law.
TEST(ContactLaws, ContactElasticIsTheFacetOfWeightOne) {
  const double modulus = 3.7e8, reference_area = 2.3e-5, area = 1.1e-5;
  for (const double volume : {1e-12, 3e-9, 5e-7}) {
    const auto same = [&](auto law) {
      using Law = decltype(law);
      const NormalElastic<double> pair =
          Law::contact_elastic(modulus, reference_area, volume, area);
      const NormalElastic<double> facet =
          Law::facet_elastic(1.0, modulus, reference_area, volume, area);
      EXPECT_EQ(pair.force, facet.force) << Law::kName << " " << volume;
      EXPECT_EQ(pair.stiffness, facet.stiffness) << Law::kName << " " << volume;
      EXPECT_EQ(pair.energy, facet.energy) << Law::kName << " " << volume;
      EXPECT_GT(pair.force, 0.0);
    };
    same(VolumeLaw{});
    same(VolumePaperLaw{});
  }
}

// The default law's pressure is the paper's above the switch volume, and its energy is continuous
// there.
TEST(ContactLaws, DefaultPressureMeetsThePapersAtTheSwitch) {
  const double modulus = 3.7e8, reference_area = 2.3e-5;
  const double switch_volume = reference_area * std::sqrt(reference_area);
  const VolumePressure<double> above =
      VolumeLaw::pressure(modulus, reference_area, 4 * switch_volume);
  const VolumePressure<double> paper =
      VolumePaperLaw::pressure(modulus, reference_area, 4 * switch_volume);
  EXPECT_EQ(above.pressure, paper.pressure);
  EXPECT_EQ(above.slope, paper.slope);
  const VolumePressure<double> below =
      VolumeLaw::pressure(modulus, reference_area, switch_volume * (1 - 1e-9));
  const VolumePressure<double> over =
      VolumeLaw::pressure(modulus, reference_area, switch_volume * (1 + 1e-9));
  EXPECT_NEAR(below.energy, over.energy, 1e-8 * over.energy);
  EXPECT_NEAR(below.pressure, over.pressure, 1e-8 * over.pressure);
}

}  // namespace
}  // namespace talus
