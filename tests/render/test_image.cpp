// Tests of render/image: PNG round trip, errors that name the path.
#include "render/image.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace clothsim::render {
namespace {

std::string scratch_path(const std::string& name) {
  const std::filesystem::path directory = std::filesystem::path(CLOTHSIM_TEST_TMPDIR) / "render";
  std::filesystem::create_directories(directory);
  return (directory / name).string();
}

TEST(Png, RoundTripsEveryPixelAndTheOrientation) {
  Image image;
  image.width = 7;  // odd: rows are not 4-byte aligned
  image.height = 5;
  image.rgb.resize(7 * 5 * 3);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = static_cast<std::uint8_t>(i * 37 % 256);
  const std::string path = scratch_path("round_trip.png");
  write_png(path, image);
  const Image back = read_png(path);
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.rgb, image.rgb);
}

TEST(Png, ErrorsNameThePath) {
  Image image;
  image.width = 2;
  image.height = 2;
  image.rgb.assign(12, 0);
  try {
    write_png("/nonexistent-folder/x.png", image);
    FAIL() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent-folder/x.png"), std::string::npos) << error.what();
  }
  if (std::filesystem::exists("/dev/full")) {
    EXPECT_THROW(write_png("/dev/full", image), std::runtime_error);
  }
  Image wrong = image;
  wrong.rgb.resize(5);
  EXPECT_THROW(write_png(scratch_path("wrong.png"), wrong), std::runtime_error);
  EXPECT_THROW(read_png(scratch_path("missing.png")), std::runtime_error);
}

}  // namespace
}  // namespace clothsim::render
