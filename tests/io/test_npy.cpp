// Tests of io/npy: bit-exact round trips through read_npy and through numpy itself, the header
// layout the format requires (magic, 64-byte alignment, reserved room for the frame count), and
// the error messages.
//
// The numpy tests run the real numpy.load, the reader our users have, rather than a
// reimplementation of it. They must not skip: scripts/install-deps.sh installs python3-numpy, and
// a missing numpy fails with a message saying how to fix it.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/npy.h"
#include "test_checks.h"

namespace clothsim {
namespace {

using checks::contains;
using checks::python_with_numpy;
using checks::thrown_message;

std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_file_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Values that need all 17 significant digits, or are special to the encoding.
std::vector<double> awkward_values() {
  return {0.1,
          0.1 * 3 + 1e-17,
          1.0 / 3.0,
          std::numbers::pi,
          std::nextafter(1.0, 2.0),
          -0.0,
          0.0,
          1e300,
          -1e-300,
          std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest(),
          std::numeric_limits<double>::denorm_min(),
          std::numeric_limits<double>::min(),
          std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity(),
          -123456.78901234567};
}

// Value number k of a test array: the awkward values first, then 0.1 k + 1e-17 k patterns.
double test_value(std::size_t k) {
  static const std::vector<double> awkward = awkward_values();
  if (k < awkward.size()) return awkward[k];
  const double sign = k % 2 == 0 ? 1.0 : -1.0;
  return sign * (0.1 * static_cast<double>(k) + 1e-17 * static_cast<double>(k));
}

std::vector<Vec3> test_frame(std::size_t frame, std::size_t items) {
  std::vector<Vec3> points(items);
  for (std::size_t item = 0; item < items; ++item) {
    const std::size_t k = 3 * (frame * items + item);
    points[item] = {test_value(k), test_value(k + 1), test_value(k + 2)};
  }
  return points;
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

void expect_bit_exact(const std::vector<double>& actual, std::size_t count) {
  ASSERT_EQ(actual.size(), count);
  for (std::size_t k = 0; k < count; ++k) {
    EXPECT_TRUE(same_bits(actual[k], test_value(k))) << "value " << k << ": " << actual[k] << " vs " << test_value(k);
  }
}

// The parts of a version 1.0 preamble.
struct Header {
  std::size_t total_bytes = 0;  // magic + version + length + dict + padding
  std::string dict;             // the header text, padding and '\n' included
};

Header parse_v1_header(const std::string& bytes) {
  Header header;
  if (bytes.size() < 10) return header;
  const std::size_t length =
      static_cast<unsigned char>(bytes[8]) | (static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8);
  header.total_bytes = 10 + length;
  header.dict = bytes.substr(10, length);
  return header;
}

// A file with a hand-made preamble, for the reader's error paths.
void write_raw_npy(const std::string& path, const std::string& dict, std::size_t data_values, unsigned major = 1) {
  std::string bytes = "\x93NUMPY";
  bytes += static_cast<char>(major);
  bytes += '\0';
  const std::size_t length = dict.size();
  const std::size_t length_bytes = major == 1 ? 2 : 4;
  for (std::size_t byte = 0; byte < length_bytes; ++byte) bytes += static_cast<char>((length >> (8 * byte)) & 0xffu);
  bytes += dict;
  for (std::size_t k = 0; k < data_values; ++k) {
    const double value = test_value(k);
    bytes.append(reinterpret_cast<const char*>(&value), sizeof(value));
  }
  write_file_bytes(path, bytes);
}

// --- Python ---

constexpr const char* kNoNumpy =
    "no Python interpreter with numpy found (tried $CLOTHSIM_PYTHON, python3, /usr/bin/python3): run "
    "scripts/install-deps.sh, which installs python3-numpy, or set CLOTHSIM_PYTHON to a python with numpy";

struct PythonResult {
  int status = -1;
  std::string output;  // stdout and stderr
};

// Runs `script` (no double quotes, dollars or backquotes: it goes inside "..." for /bin/sh) with
// the file's path in the environment variable NPY_PATH, so no path needs quoting.
PythonResult run_python(const std::string& script, const std::string& npy_path) {
  PythonResult result;
  ::setenv("NPY_PATH", npy_path.c_str(), 1);
  const std::string command =
      python_with_numpy() + " -c \"import os, numpy; path = os.environ['NPY_PATH']; " + script + "\" 2>&1";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[4096];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0) result.output.append(buffer, got);
  result.status = ::pclose(pipe);
  return result;
}

// Loads `path` with numpy.load, checks shape and dtype, and returns every value (C order) as
// parsed from Python's repr, which round-trips doubles exactly.
std::vector<double> numpy_load(const std::string& path, const std::string& python_shape) {
  const PythonResult result = run_python("a = numpy.load(path); assert a.shape == " + python_shape +
                                             ", a.shape; assert a.dtype == numpy.float64, a.dtype; "
                                             "print(' '.join(repr(float(x)) for x in a.ravel()))",
                                         path);
  EXPECT_EQ(result.status, 0) << "numpy.load(" << path << ") failed:\n" << result.output;
  std::vector<double> values;
  std::istringstream tokens(result.output);
  std::string token;
  while (tokens >> token) values.push_back(std::strtod(token.c_str(), nullptr));
  return values;
}

// --- Streaming writer ---

TEST(WriteNpy, Int32ArrayRoundTripsAndSaysItsDtype) {
  const std::string path = checks::scratch_path("io", "int32.npy");
  const std::vector<std::int32_t> values = {0, 1, -7, 2147483647, -2147483647 - 1, 42};
  const std::array<std::size_t, 2> shape = {3, 2};
  write_npy(path, values, shape);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("'descr': '<i4'"), std::string::npos);
  EXPECT_EQ((bytes.size() - values.size() * 4u) % 64u, 0u) << "4 bytes a value after an aligned header";
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{3, 2}));
  ASSERT_EQ(array.data.size(), values.size());
  for (std::size_t k = 0; k < values.size(); ++k) EXPECT_EQ(array.data[k], static_cast<double>(values[k]));
}

TEST(NpyWriter, StreamedVec3FramesRoundTripBitExact) {
  const std::string path = checks::scratch_path("io", "streamed_vec3.npy");
  constexpr std::size_t frames = 4;
  constexpr std::size_t items = 5;
  {
    NpyWriter writer(path, items);
    for (std::size_t frame = 0; frame < frames; ++frame) writer.append(test_frame(frame, items));
    EXPECT_EQ(writer.frames(), frames);
    writer.close();
  }
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{frames, items, 3}));
  expect_bit_exact(array.data, frames * items * 3);
}

TEST(NpyWriter, StreamedDoubleFramesWithOtherComponentCounts) {
  const std::string path = checks::scratch_path("io", "streamed_double.npy");
  constexpr std::size_t frames = 3;
  constexpr std::size_t items = 7;
  constexpr std::size_t components = 2;
  NpyWriter writer(path, items, components);
  for (std::size_t frame = 0; frame < frames; ++frame) {
    std::vector<double> values(items * components);
    for (std::size_t k = 0; k < values.size(); ++k) values[k] = test_value(frame * values.size() + k);
    writer.append(values);
  }
  writer.close();
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{frames, items, components}));
  expect_bit_exact(array.data, frames * items * components);
}

class NpyWriterFrameCount : public testing::TestWithParam<std::size_t> {};

TEST_P(NpyWriterFrameCount, HeaderIsAlignedAndRewrittenOnClose) {
  const std::size_t frames = GetParam();
  constexpr std::size_t items = 5;
  const std::string path = checks::scratch_path("io", "frames_" + std::to_string(frames) + ".npy");
  NpyWriter writer(path, items);
  writer.flush();  // puts the provisional header on disk
  const Header provisional = parse_v1_header(read_file_bytes(path));
  for (std::size_t frame = 0; frame < frames; ++frame) writer.append(test_frame(frame, items));
  writer.close();

  const std::string bytes = read_file_bytes(path);
  ASSERT_GE(bytes.size(), 10U);
  EXPECT_EQ(bytes.substr(0, 6), "\x93NUMPY");
  EXPECT_EQ(bytes[6], '\x01') << "major version";
  EXPECT_EQ(bytes[7], '\x00') << "minor version";
  const Header header = parse_v1_header(bytes);
  EXPECT_EQ(header.total_bytes % 64, 0U);
  EXPECT_EQ(header.total_bytes, provisional.total_bytes) << "the header is rewritten in place";
  ASSERT_FALSE(header.dict.empty());
  EXPECT_EQ(header.dict.back(), '\n');
  EXPECT_TRUE(contains(provisional.dict, "'shape': (0, 5, 3)"));
  EXPECT_TRUE(contains(header.dict,
                       "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(frames) + ", 5, 3), }"));
  // Room for a 20-digit frame count: the 1-digit provisional count leaves >= 19 spaces of padding.
  const std::size_t padding = provisional.dict.size() - 1 - provisional.dict.find_last_not_of(" \n");
  EXPECT_GE(padding, 19U) << provisional.dict;
  EXPECT_EQ(bytes.size(), header.total_bytes + frames * items * 3 * sizeof(double));

  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{frames, items, 3}));
  expect_bit_exact(array.data, frames * items * 3);
}

INSTANTIATE_TEST_SUITE_P(Frames, NpyWriterFrameCount, testing::Values(0U, 1U, 1000U), testing::PrintToStringParamName());

TEST(NpyWriter, FlushMakesTheFramesSoFarReadable) {
  const std::string path = checks::scratch_path("io", "flushed.npy");
  NpyWriter writer(path, 2);
  writer.append(test_frame(0, 2));
  writer.append(test_frame(1, 2));
  writer.flush();
  EXPECT_EQ(read_npy(path).shape, (std::vector<std::size_t>{2, 2, 3}));
  writer.append(test_frame(2, 2));
  writer.close();
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{3, 2, 3}));
  expect_bit_exact(array.data, 3 * 2 * 3);
}

TEST(NpyWriter, DestructorClosesAnUnclosedWriter) {
  const std::string path = checks::scratch_path("io", "destructor.npy");
  {
    NpyWriter writer(path, 3);
    writer.append(test_frame(0, 3));
    writer.append(test_frame(1, 3));
  }
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{2, 3, 3}));
  expect_bit_exact(array.data, 2 * 3 * 3);
}

TEST(NpyWriter, CloseIsIdempotentAndAppendAfterCloseThrows) {
  const std::string path = checks::scratch_path("io", "closed.npy");
  NpyWriter writer(path, 2);
  writer.append(test_frame(0, 2));
  writer.close();
  EXPECT_FALSE(writer.is_open());
  EXPECT_NO_THROW(writer.close());
  EXPECT_NO_THROW(writer.flush());
  EXPECT_TRUE(contains(thrown_message([&] { writer.append(test_frame(1, 2)); }), path));
  EXPECT_EQ(writer.frames(), 1U);
  EXPECT_EQ(read_npy(path).shape, (std::vector<std::size_t>{1, 2, 3}));
}

TEST(NpyWriter, WrongFrameSizeThrowsAndLeavesTheFileValid) {
  const std::string path = checks::scratch_path("io", "wrong_size.npy");
  NpyWriter writer(path, 4);
  writer.append(test_frame(0, 4));
  const std::string message = thrown_message([&] { writer.append(test_frame(1, 3)); });
  EXPECT_TRUE(contains(message, path));
  EXPECT_TRUE(contains(message, "3 points, expected 4"));
  const std::vector<double> too_many(13, 1.0);
  EXPECT_TRUE(
      contains(thrown_message([&] { writer.append(std::span<const double>(too_many)); }), "13 values, expected 12"));
  EXPECT_EQ(writer.frames(), 1U);
  writer.append(test_frame(1, 4));
  writer.close();
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{2, 4, 3}));
  expect_bit_exact(array.data, 2 * 4 * 3);
}

TEST(NpyWriter, Vec3FramesNeedThreeComponents) {
  const std::string path = checks::scratch_path("io", "two_components.npy");
  NpyWriter writer(path, 2, 2);
  EXPECT_TRUE(contains(thrown_message([&] { writer.append(test_frame(0, 2)); }), "3 components"));
  EXPECT_EQ(writer.frames(), 0U);
}

TEST(NpyWriter, MoveTransfersTheOpenFile) {
  const std::string path = checks::scratch_path("io", "moved.npy");
  NpyWriter first(path, 2);
  first.append(test_frame(0, 2));
  NpyWriter second(std::move(first));
  second.append(test_frame(1, 2));
  EXPECT_EQ(second.frames(), 2U);
  EXPECT_NO_THROW(first.close());  // NOLINT(bugprone-use-after-move): a moved-from writer is closed

  const std::string other_path = checks::scratch_path("io", "moved_over.npy");
  NpyWriter third(other_path, 2);
  third = std::move(second);  // closes other_path (0 frames), takes over path
  third.append(test_frame(2, 2));
  third.close();
  EXPECT_EQ(read_npy(other_path).shape, (std::vector<std::size_t>{0, 2, 3}));
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{3, 2, 3}));
  expect_bit_exact(array.data, 3 * 2 * 3);
}

TEST(NpyWriter, UncreatableFileThrowsWithPathAndReason) {
  const std::string path = checks::scratch_path("io", "no_such_directory/frames.npy");
  const std::string message = thrown_message([&] { NpyWriter writer(path, 3); });
  EXPECT_TRUE(contains(message, path));
  EXPECT_TRUE(contains(message, "No such file or directory"));
}

// /dev/full accepts open() and fails every write with ENOSPC: the full-disk case.
TEST(NpyWriter, WriteFailuresAreReported) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "needs /dev/full";
  const std::string path = "/dev/full";
  NpyWriter writer(path, 1000);
  // Frames go into a stdio buffer first; the failure shows once it is flushed.
  const std::string message = thrown_message([&] {
    for (std::size_t frame = 0; frame < 1000; ++frame) writer.append(test_frame(0, 1000));
  });
  EXPECT_TRUE(contains(message, path));
  EXPECT_TRUE(contains(message, "No space left on device"));
  EXPECT_TRUE(contains(thrown_message([&] { writer.append(test_frame(0, 1000)); }), "earlier write failure"));
  EXPECT_TRUE(contains(thrown_message([&] { writer.close(); }), "No space left on device"));
  EXPECT_NO_THROW(writer.close());

  EXPECT_NO_THROW({
    NpyWriter unclosed(path, 2);
    unclosed.append(test_frame(0, 2));
  }) << "the destructor swallows the close failure";

  const std::vector<double> data(4, 1.0);
  const std::vector<std::size_t> shape = {4};
  EXPECT_TRUE(contains(thrown_message([&] { write_npy(path, data, shape); }), "No space left on device"));
}

// --- Whole arrays ---

TEST(WriteNpy, RoundTripsAnyShape) {
  const std::vector<std::vector<std::size_t>> shapes = {{2, 3, 4}, {5}, {}, {0, 3}, {1, 1, 1, 7}};
  for (const std::vector<std::size_t>& shape : shapes) {
    std::size_t count = 1;
    for (const std::size_t extent : shape) count *= extent;
    std::vector<double> data(count);
    for (std::size_t k = 0; k < count; ++k) data[k] = test_value(k);
    const std::string path = checks::scratch_path("io", "whole_" + std::to_string(shape.size()) + "d.npy");
    write_npy(path, data, shape);
    const Header header = parse_v1_header(read_file_bytes(path));
    EXPECT_EQ(header.total_bytes % 64, 0U);
    const NpyArray array = read_npy(path);
    EXPECT_EQ(array.shape, shape);
    expect_bit_exact(array.data, count);
  }
}

TEST(WriteNpy, SizeMismatchAndUncreatableFileThrow) {
  const std::vector<double> data(5, 1.0);
  const std::vector<std::size_t> shape = {2, 3};
  const std::string path = checks::scratch_path("io", "mismatch.npy");
  const std::string message = thrown_message([&] { write_npy(path, data, shape); });
  EXPECT_TRUE(contains(message, path));
  EXPECT_TRUE(contains(message, "(2, 3)"));
  const std::string missing = checks::scratch_path("io", "no_such_directory/whole.npy");
  const std::vector<std::size_t> flat = {5};
  EXPECT_TRUE(contains(thrown_message([&] { write_npy(missing, data, flat); }), missing));
}

// --- Reader ---

TEST(ReadNpy, ReadsVersion2Headers) {
  const std::string path = checks::scratch_path("io", "version2.npy");
  write_raw_npy(path, "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }\n", 6, 2);
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{2, 3}));
  expect_bit_exact(array.data, 6);
}

TEST(ReadNpy, AcceptsReorderedKeysAndDoubleQuotes) {
  const std::string path = checks::scratch_path("io", "reordered.npy");
  write_raw_npy(path, "{\"shape\": (4,), \"fortran_order\": False, \"descr\": \"<f8\"}   \n", 4);
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{4}));
  expect_bit_exact(array.data, 4);
}

TEST(ReadNpy, RejectsWhatItCannotRead) {
  const std::string path = checks::scratch_path("io", "bad.npy");
  const auto message_for = [&](const std::string& dict, std::size_t values, unsigned major = 1) {
    write_raw_npy(path, dict, values, major);
    return thrown_message([&] { read_npy(path); });
  };
  EXPECT_TRUE(contains(message_for("{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }\n", 2), "'<f4'"));
  EXPECT_TRUE(contains(message_for("{'descr': '>f8', 'fortran_order': False, 'shape': (2,), }\n", 2), "'>f8'"));
  EXPECT_TRUE(contains(message_for("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 2), }\n", 4), "Fortran"));
  EXPECT_TRUE(contains(message_for("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }\n", 11), "truncated"));
  EXPECT_TRUE(contains(message_for("{'descr': '<f8', 'shape': (2,), }\n", 2), "are all required"));
  EXPECT_TRUE(contains(message_for("{'descr': '<f8', 'fortran_order': False, 'shape': (2), }\n", 2), "(n,)"));
  EXPECT_TRUE(contains(message_for("{'descr': '<f8', 'fortran_order': False, 'shape': (2,), 'x': 1}\n", 2), "'x'"));
  EXPECT_TRUE(
      contains(message_for("{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }\n", 2, 3), "version 3.0"));
  EXPECT_TRUE(contains(message_for("{'descr': '<f8', 'fortran_order': False, 'shape': (-2,), }\n", 2), "malformed"));

  write_file_bytes(path, "not a numpy file at all");
  const std::string message = thrown_message([&] { read_npy(path); });
  EXPECT_TRUE(contains(message, path));
  EXPECT_TRUE(contains(message, "not a .npy file"));
  write_file_bytes(path, "\x93NUM");
  EXPECT_TRUE(contains(thrown_message([&] { read_npy(path); }), "truncated"));
  EXPECT_TRUE(contains(thrown_message([&] { read_npy(checks::scratch_path("io", "does_not_exist.npy")); }),
                       "does_not_exist.npy"));
}

// --- numpy itself ---

TEST(NpyNumpy, NumpyLoadsStreamedFramesBitExact) {
  ASSERT_FALSE(python_with_numpy().empty()) << kNoNumpy;
  const std::string path = checks::scratch_path("io", "numpy_streamed.npy");
  constexpr std::size_t frames = 3;
  constexpr std::size_t items = 4;
  NpyWriter writer(path, items);
  for (std::size_t frame = 0; frame < frames; ++frame) writer.append(test_frame(frame, items));
  writer.close();
  expect_bit_exact(numpy_load(path, "(3, 4, 3)"), frames * items * 3);

  // One element by index, as a user would: a[2, 1, 0] is value (2*4 + 1)*3 + 0.
  const PythonResult element = run_python("a = numpy.load(path); print(repr(float(a[2, 1, 0])))", path);
  ASSERT_EQ(element.status, 0) << element.output;
  EXPECT_TRUE(same_bits(std::strtod(element.output.c_str(), nullptr), test_value(27))) << element.output;
}

TEST(NpyNumpy, NumpyLoadsEveryFrameCount) {
  ASSERT_FALSE(python_with_numpy().empty()) << kNoNumpy;
  for (const std::size_t frames : {0U, 1U, 1000U}) {
    const std::string path = checks::scratch_path("io", "numpy_frames_" + std::to_string(frames) + ".npy");
    NpyWriter writer(path, 2);
    for (std::size_t frame = 0; frame < frames; ++frame) writer.append(test_frame(frame, 2));
    writer.close();
    expect_bit_exact(numpy_load(path, "(" + std::to_string(frames) + ", 2, 3)"), frames * 2 * 3);
  }
}

TEST(NpyNumpy, NumpyLoadsWholeArrays) {
  ASSERT_FALSE(python_with_numpy().empty()) << kNoNumpy;
  const std::vector<std::pair<std::vector<std::size_t>, std::string>> cases = {
      {{2, 3, 4}, "(2, 3, 4)"}, {{5}, "(5,)"}, {{}, "()"}, {{0, 3}, "(0, 3)"}};
  for (const auto& [shape, python_shape] : cases) {
    std::size_t count = 1;
    for (const std::size_t extent : shape) count *= extent;
    std::vector<double> data(count);
    for (std::size_t k = 0; k < count; ++k) data[k] = test_value(k);
    const std::string path = checks::scratch_path("io", "numpy_whole_" + std::to_string(shape.size()) + "d.npy");
    write_npy(path, data, shape);
    expect_bit_exact(numpy_load(path, python_shape), count);
  }
}

TEST(NpyNumpy, ReadNpyReadsWhatNumpySaves) {
  ASSERT_FALSE(python_with_numpy().empty()) << kNoNumpy;
  const std::string path = checks::scratch_path("io", "numpy_saved.npy");
  PythonResult saved = run_python("numpy.save(path, (numpy.arange(24, dtype='<f8') * 0.1).reshape(2, 3, 4))", path);
  ASSERT_EQ(saved.status, 0) << saved.output;
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{2, 3, 4}));
  ASSERT_EQ(array.data.size(), 24U);
  for (std::size_t k = 0; k < 24; ++k) EXPECT_TRUE(same_bits(array.data[k], static_cast<double>(k) * 0.1)) << k;

  saved = run_python("numpy.save(path, numpy.ones((2, 3), dtype='<f4'))", path);
  ASSERT_EQ(saved.status, 0) << saved.output;
  EXPECT_TRUE(contains(thrown_message([&] { read_npy(path); }), "'<f4'"));
  saved = run_python("numpy.save(path, numpy.asfortranarray(numpy.ones((2, 3))))", path);
  ASSERT_EQ(saved.status, 0) << saved.output;
  EXPECT_TRUE(contains(thrown_message([&] { read_npy(path); }), "Fortran"));
}

}  // namespace
}  // namespace clothsim
