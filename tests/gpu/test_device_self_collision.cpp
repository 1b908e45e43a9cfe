// Self-collision with the Vulkan backend (collision/self_contacts.h): with the explicit methods the
// host's self pass runs between the device's steps, the device integrator asked for one step at a
// time (Simulation::host_works_between_steps), after the device's own obstacle pass; implicit Euler
// runs the device's pass (gpu/device_self_contacts.h), which the memory check counts. Held against
// the CPU's runs and the brute-force crossing count (tests/collision/sheet_crossings.h) at every
// frame.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "device_models.h"
#include "folded_sheet.h"
#include "gpu/device_implicit_euler.h"
#include "gpu/device_self_contacts.h"
#include "io/restored_run.h"
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
  // for 0.15 s on the device in float64, never crossed at any frame. With RKF45 the host's self
  // pass runs between the device's steps: the CPU's run within rounding (measured on lavapipe:
  // 1.2e-9 m).
  const BackendSettings vulkan{Backend::vulkan, 0, request(Precision::float64)};
  Simulation device = testing::folded_sheet(IntegratorKind::rkf45, 2e-4, 1, vulkan);
  Simulation cpu = testing::folded_sheet(IntegratorKind::rkf45, 2e-4, 1, {Backend::cpu, 0, PrecisionRequest::float64});
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

TEST(DeviceSelfCollision, ImplicitEulerRunsTheSelfPassOnTheDevice) {
  // The folded sheet with implicit Euler, whose device runs the self pass itself
  // (gpu/device_self_contacts.h: the CPU's response law in Jacobi iterations, so not the CPU's
  // bits): never crossed at any frame, no energy made (the obstacle and self passes' work booked
  // on the device, the balance closed as on the CPU), and the sheet where the CPU's lies, within
  // 2 mm (measured on lavapipe: 0.94 mm; the balance closes to -0.141 J, the CPU's to -0.149 J).
  const BackendSettings vulkan{Backend::vulkan, 0, request(Precision::float64)};
  Simulation device = testing::folded_sheet(IntegratorKind::implicit_euler, 1e-3, 1, vulkan);
  Simulation cpu = testing::folded_sheet(IntegratorKind::implicit_euler, 1e-3, 1);
  const double start_energy = device.energy().total();
  for (int frame = 1; frame <= 15; ++frame) {
    ASSERT_TRUE(device.advance_to(0.01 * frame)) << device.failure()->message;
    ASSERT_TRUE(cpu.advance_to(0.01 * frame)) << cpu.failure()->message;
    EXPECT_EQ(count_sheet_crossings(device.model(), device.state().position), 0u) << "frame " << frame;
    EXPECT_LE(device.energy().total(), start_energy + 1e-9) << "frame " << frame;
  }
  // The two passes' work booked together: the balance (implicit Euler's numerical damping, mostly)
  // as the CPU's within 10 % (measured on lavapipe: -0.141 J against -0.149 J, the contact work
  // 0.063 J against 0.072 J). GpuTest.SelfContactsKeepTheLedgerOfWhatTheyMoved holds the ledger
  // the booking reads.
  const double balance = device.energy_balance().error();
  const double cpu_balance = cpu.energy_balance().error();
  EXPECT_NEAR(balance, cpu_balance, 0.1 * std::abs(cpu_balance));
  EXPECT_GT(device.energy_balance().contact_work, 0.03);
  EXPECT_LT(largest_distance(device.state().position, cpu.state().position), 2e-3);
  EXPECT_GT(device.contact_statistics().self_contact_steps, 1000u);
}

// tear-crumple, whole, on the device (implicit Euler there, its obstacle, self-collision and event
// passes on the host between the steps; about 25 s on lavapipe): it tears, creases, folds onto
// itself and never crosses itself, as on the CPU.
TEST(DeviceSelfCollision, TearCrumpleTearsCreasesAndNeverCrosses) {
  SceneSpec spec = builtin_scene("tear-crumple");
  spec.backend = BackendSettings{Backend::vulkan, 0, std::nullopt};
  testing::expect_tear_crumple_run(spec, spec.output.duration, 30);
}

// Self-collision switched off and on again between frames (the viewer's panel, a script): the
// device's pass stops and starts with it, its arrays made for it, and the sheet stays uncrossed
// while it is on.
TEST(DeviceSelfCollision, ImplicitEulerSwitchesItsSelfPassBetweenFrames) {
  const BackendSettings vulkan{Backend::vulkan, 0, request(Precision::float64)};
  Simulation simulation = testing::folded_sheet(IntegratorKind::implicit_euler, 1e-3, 1, vulkan);
  simulation.set_self_collision(false);
  ASSERT_TRUE(simulation.advance_to(0.01)) << simulation.failure()->message;
  EXPECT_EQ(simulation.contact_statistics().self_contact_steps, 0u);
  simulation.set_self_collision(true);
  for (int frame = 2; frame <= 8; ++frame) {
    ASSERT_TRUE(simulation.advance_to(0.01 * frame)) << simulation.failure()->message;
    EXPECT_EQ(count_sheet_crossings(simulation.model(), simulation.state().position), 0u) << "frame " << frame;
  }
  const std::uint64_t on = simulation.contact_statistics().self_contact_steps;
  EXPECT_GT(on, 100u);
  simulation.set_self_collision(false);
  ASSERT_TRUE(simulation.advance_to(0.09)) << simulation.failure()->message;
  EXPECT_EQ(simulation.contact_statistics().self_contact_steps, on);
}

// tear-crumple saved while it folds onto itself and restored: the restored run goes on bit for bit
// (the device's self pass keeps nothing between advances that a checkpoint lacks: it finds its
// candidates again at each advance's start, and the host's pass that finishes a step is new each
// time).
TEST(DeviceSelfCollision, ARestoredRunGoesOnBitForBit) {
  SceneSpec spec = builtin_scene("tear-crumple");
  spec.backend = BackendSettings{Backend::vulkan, 0, std::nullopt};
  const ContactStatistics contacts = testing::expect_restored_run_matches(spec, 0.12, 0.18, 2);
  EXPECT_GT(contacts.self_contact_steps, 1000u);
}

// The memory check before a run counts the device's self pass (DeviceSelfContacts::bytes_for) and
// the obstacle pass's arrays it books its work in: a square sheet of implicit Euler whose other
// arrays fit the device but whose self pass does not is refused with collision.self, before
// anything is allocated, and passes without it.
TEST(DeviceSelfCollision, TheMemoryCheckCountsTheSelfPass) {
  IntegratorSettings settings;
  settings.kind = IntegratorKind::implicit_euler;
  const auto bytes = [&](std::size_t side, bool self) {
    return gpu::DeviceImplicitEuler::device_bytes_for(lattice_counts(side, side), 4, Precision::float64, 0, settings,
                                                      self);
  };
  const LatticeCounts small = lattice_counts(64, 64);
  EXPECT_GE(bytes(64, true) - bytes(64, false), gpu::DeviceSelfContacts::bytes_for(small, Precision::float64));
  const std::uint64_t memory = gpu::Device(gpu::DeviceOptions{0, false}).info().device_local_bytes;
  std::size_t side = 64;
  while (bytes(side, true) <= memory) side += side / 16;
  ASSERT_LT(bytes(side, false), memory) << "a side where only the self pass does not fit: " << side;
  const BackendSettings backend = testing::vulkan(Precision::float64);
  try {
    check_backend_fits(lattice_counts(side, side), 4, settings, backend, 0, true);
    FAIL() << side << " x " << side << " with self-collision fits";
  } catch (const BackendError& error) {
    EXPECT_NE(std::string(error.what()).find("the scene needs"), std::string::npos) << error.what();
  }
  EXPECT_NO_THROW(check_backend_fits(lattice_counts(side, side), 4, settings, backend, 0, false));
}

}  // namespace
}  // namespace clothsim
