// Self-collision with the Vulkan backend (collision/self_contacts.h): the host's self pass runs
// between the device's steps, the device integrator asked for one step at a time
// (Simulation::host_works_between_steps), after the device's own obstacle pass. Held against the
// CPU's runs and the brute-force crossing count (tests/collision/sheet_crossings.h) at every frame.
#include <gtest/gtest.h>

#include <string>

#include "folded_sheet.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene_simulation.h"
#include "sheet_crossings.h"
#include "sim/backend.h"
#include "sim/simulation.h"
#include "tear_crumple_run.h"

namespace clothsim {
namespace {

using testing::count_sheet_crossings;
using testing::largest_distance;

TEST(DeviceSelfCollision, AFoldedSheetLandsOnItselfAsOnTheCpu) {
  // A soft sheet folded in half falls onto a floor and onto itself (tests/collision/folded_sheet.h),
  // for 0.15 s on the device in float64, with implicit Euler and with RKF45: never crossed at any
  // frame, and the CPU's run within rounding (measured on lavapipe: 1.4e-16 m and 1.2e-9 m).
  for (IntegratorKind kind : {IntegratorKind::implicit_euler, IntegratorKind::rkf45}) {
    SCOPED_TRACE(std::string(to_string(kind)));
    const double step = kind == IntegratorKind::implicit_euler ? 1e-3 : 2e-4;
    Simulation device =
        testing::folded_sheet(kind, step, 1, BackendSettings{Backend::vulkan, 0, request(Precision::float64)});
    Simulation cpu = testing::folded_sheet(kind, step, 1);
    for (int frame = 1; frame <= 15; ++frame) {
      ASSERT_TRUE(device.advance_to(0.01 * frame)) << device.failure()->message;
      ASSERT_TRUE(cpu.advance_to(0.01 * frame)) << cpu.failure()->message;
      EXPECT_EQ(count_sheet_crossings(device.model(), device.state().position), 0u) << "frame " << frame;
    }
    EXPECT_LT(largest_distance(device.state().position, cpu.state().position), 1e-8);
    EXPECT_EQ(device.integrator_stats().accepted_steps, cpu.integrator_stats().accepted_steps);
    // Which particles are within the thickness of the sheet in a step can differ by rounding.
    const double contacts = static_cast<double>(device.contact_statistics().self_contact_steps);
    const double cpu_contacts = static_cast<double>(cpu.contact_statistics().self_contact_steps);
    EXPECT_GT(cpu_contacts, 1000.0);
    EXPECT_NEAR(contacts, cpu_contacts, 0.01 * cpu_contacts);
  }
}

// tear-crumple, whole, on the device (implicit Euler there, its obstacle, self-collision and event
// passes on the host between the steps; about 25 s on lavapipe): it tears, creases, folds onto
// itself and never crosses itself, as on the CPU.
TEST(DeviceSelfCollision, TearCrumpleTearsCreasesAndNeverCrosses) {
  SceneSpec spec = builtin_scene("tear-crumple");
  spec.backend = BackendSettings{Backend::vulkan, 0, std::nullopt};
  testing::expect_tear_crumple_run(spec, spec.output.duration, 30);
}

}  // namespace
}  // namespace clothsim
