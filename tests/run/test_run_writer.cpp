// Tests of run/run_writer for a torn sheet, built through the library (Simulation::cut_connectors):
// the tearing columns of energy.csv, the sheet_changes of summary.json, connectors.npy and
// connector_break_time.npy (enough to rebuild each frame's live connectors), and a split
// final.obj; and for a sheet on a floor, the contact columns and keys (collision/). The files of an
// intact run are tested end to end in tests/apps/test_cli.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "io/npy.h"
#include "run/run_writer.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene_simulation.h"
#include "test_checks.h"

namespace clothsim {
namespace {

using checks::contains;
namespace fs = std::filesystem;

struct Csv {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};

Csv read_csv(const fs::path& path) {
  Csv csv;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::istringstream header(line);
  for (std::string column; std::getline(header, column, ',');) csv.columns.push_back(column);
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::vector<double> row;
    for (std::string field; std::getline(fields, field, ',');) row.push_back(std::stod(field));
    csv.rows.push_back(row);
  }
  return csv;
}

std::size_t column(const Csv& csv, const std::string& name) {
  for (std::size_t k = 0; k < csv.columns.size(); ++k) {
    if (csv.columns[k] == name) return k;
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

TEST(RunWriter, ContactRunRecordsContacts) {
  // A 6 x 6 sheet hanging from one anchor onto a floor 2 m below it (collision/).
  const SceneSpec spec =
      parse_scene(R"({"name": "floor", "paper_args": [6, 6, 1, 4, 1, 1400, 200, 80, 5, 1]})", "test");
  ClothModel model = build_model(spec);
  Collider floor;
  floor.shape = ColliderShape::plane;
  floor.point = Vec3{0.0, -2.0, 0.0};
  model.colliders.push_back(floor);
  Simulation simulation = testing::one_thread_simulation(spec, std::move(model));
  const fs::path out = fs::path(CLOTHSIM_TEST_TMPDIR) / "io" / "contact_run";
  fs::remove_all(out);
  RunWriter writer(out, RunInfo{"test", "test"});
  writer.begin(spec, simulation);
  writer.write_frame(simulation);
  ASSERT_TRUE(simulation.advance_to(1.5));
  writer.write_frame(simulation);
  writer.finish(simulation, RunStatus::completed, 1.0);

  const Csv energy = read_csv(out / RunWriter::kEnergyFile);
  ASSERT_EQ(energy.rows.size(), 2u);
  const std::size_t contacts = column(energy, "contacts");
  const std::size_t work = column(energy, "contact_work");
  EXPECT_EQ(energy.rows[0][contacts], 0.0);
  EXPECT_EQ(energy.rows[1][contacts], static_cast<double>(simulation.contact_statistics().contacts));
  EXPECT_GT(energy.rows[1][contacts], 0.0) << "the sheet lies on the floor";
  EXPECT_LT(energy.rows[1][work], 0.0);

  std::ifstream summary_file(out / RunWriter::kSummaryFile);
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["contacts"]["colliders"], 1);
  EXPECT_EQ(summary["contacts"]["contact_steps"].get<std::uint64_t>(), simulation.contact_statistics().contact_steps);
  EXPECT_GE(summary["contacts"]["contact_steps"].get<double>(), energy.rows[1][contacts]);
  EXPECT_EQ(summary["contacts"]["contact_work"].get<double>(), energy.rows[1][work]);
  EXPECT_EQ(summary["energy"]["final"]["contact_work"].get<double>(), energy.rows[1][work]);
  EXPECT_TRUE(summary["timings"].contains("collisions"));
}

TEST(RunWriter, TornRunRecordsItsTopologyAndChanges) {
  // A 6 x 6 sheet hanging from one anchor; between frames 1 and 2 a cut breaks the 6 connectors
  // between rows 2 and 3.
  const SceneSpec spec = parse_scene(R"({"name": "torn", "paper_args": [6, 6, 1, 4, 1, 1400, 200, 80, 5, 1]})", "test");
  Simulation simulation = testing::one_thread_simulation(spec);
  const fs::path out = fs::path(CLOTHSIM_TEST_TMPDIR) / "io" / "torn_run";
  fs::remove_all(out);
  RunWriter writer(out, RunInfo{"test", "test"});
  writer.begin(spec, simulation);
  writer.write_frame(simulation);
  ASSERT_TRUE(simulation.advance_to(0.05));
  writer.write_frame(simulation);
  std::vector<std::uint32_t> cut;
  for (std::uint32_t e = 0; e < simulation.model().connector_count(); ++e) {
    const auto [a, b] = simulation.model().connector_particles[e];
    if (a / 6 == 2 && b == a + 6) cut.push_back(e);
  }
  ASSERT_EQ(cut.size(), 6u);
  ASSERT_TRUE(simulation.advance_to(0.07));  // between frames 1 and 2
  ASSERT_EQ(simulation.cut_connectors(cut), 6u);
  ASSERT_TRUE(simulation.advance_to(0.1));
  writer.write_frame(simulation);
  ASSERT_TRUE(simulation.advance_to(0.15));
  writer.write_frame(simulation);
  writer.finish(simulation, RunStatus::completed, 1.0);

  // energy.csv: the old columns first, in their order, then the tearing columns, then the contact columns.
  const Csv energy = read_csv(out / RunWriter::kEnergyFile);
  ASSERT_EQ(energy.columns.size(), 22u);
  EXPECT_EQ(energy.columns[19], "contact_work");
  EXPECT_EQ(energy.columns[20], "contacts");
  EXPECT_EQ(energy.columns[21], "self_contacts");
  EXPECT_EQ(energy.columns[13], "rejected_steps");
  ASSERT_EQ(energy.rows.size(), 4u);
  const std::size_t broken = column(energy, "broken_connectors");
  const std::size_t fracture = column(energy, "fracture_work");
  EXPECT_EQ(energy.rows[1][broken], 0.0);
  EXPECT_EQ(energy.rows[2][broken], 6.0);
  EXPECT_EQ(energy.rows[3][broken], 6.0);
  EXPECT_EQ(energy.rows[1][fracture], 0.0);
  EXPECT_LT(energy.rows[2][fracture], 0.0) << "the cut springs were stretched under gravity";
  EXPECT_EQ(energy.rows[3][column(energy, "max_plastic_strain")], 0.0);
  EXPECT_EQ(energy.rows[3][column(energy, "plastic_work")], 0.0);
  EXPECT_EQ(energy.rows[3][column(energy, "max_rest_angle_change")], 0.0);

  // summary.json.
  std::ifstream summary_file(out / RunWriter::kSummaryFile);
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  const nlohmann::json& changes = summary["sheet_changes"];
  EXPECT_EQ(changes["broken_connectors"], 6);
  EXPECT_GT(changes["broken_radials"].get<int>(), 6);
  EXPECT_EQ(changes["breaks"], 0) << "cuts are not events";
  EXPECT_EQ(changes["yields"], 0);
  EXPECT_EQ(changes["creases"], 0);
  EXPECT_EQ(changes["fracture_work"].get<double>(), energy.rows[3][fracture]);
  EXPECT_EQ(changes["plastic_work"].get<double>(), 0.0);
  EXPECT_TRUE(summary["timings"].contains("events"));
  EXPECT_EQ(summary["files"]["connectors.npy"]["dtype"], "int32");
  EXPECT_EQ(summary["energy"]["final"]["fracture_work"].get<double>(), energy.rows[3][fracture]);

  // connectors.npy and connector_break_time.npy rebuild each frame's live connectors.
  const NpyArray connectors = read_npy((out / RunWriter::kConnectorsFile).string());
  const ClothModel& torn = simulation.model();
  ASSERT_EQ(connectors.shape, (std::vector<std::size_t>{torn.connector_count(), 2}));
  for (std::size_t e = 0; e < torn.connector_count(); ++e) {
    EXPECT_EQ(connectors.data[2 * e], torn.connector_particles[e][0]);
    EXPECT_EQ(connectors.data[2 * e + 1], torn.connector_particles[e][1]);
  }
  const NpyArray break_time = read_npy((out / RunWriter::kBreakTimeFile).string());
  ASSERT_EQ(break_time.shape, (std::vector<std::size_t>{torn.connector_count()}));
  for (std::size_t e = 0; e < torn.connector_count(); ++e) {
    if (torn.connector_live[e] != 0) {
      EXPECT_TRUE(std::isinf(break_time.data[e])) << e;
    } else {
      EXPECT_EQ(break_time.data[e], 0.07) << "the time of the cut";
    }
    for (std::size_t frame = 0; frame < energy.rows.size(); ++frame) {
      const bool live_then = break_time.data[e] > energy.rows[frame][1];
      EXPECT_EQ(live_then, frame < 2 || torn.connector_live[e] != 0) << "connector " << e << ", frame " << frame;
    }
  }
  // connector_rest_length.npy: the rest lengths at the end, which place the split vertices.
  const NpyArray rest_length = read_npy((out / RunWriter::kRestLengthFile).string());
  EXPECT_EQ(rest_length.data, torn.connector_rest_length);
  EXPECT_EQ(summary["files"]["connector_rest_length.npy"]["unit"], "m");

  // final.obj is split along the tear.
  std::ifstream obj(out / RunWriter::kFinalMeshFile);
  std::string text((std::istreambuf_iterator<char>(obj)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(text, "torn along 6 broken connectors"));
}

}  // namespace
}  // namespace clothsim
