// Sizes of memory as people write them (core/memory_size.h): binary and decimal units, plain
// bytes, what is refused, and the printed form.
#include <gtest/gtest.h>

#include <cstdint>

#include "core/memory_size.h"

namespace clothsim {
namespace {

constexpr std::uint64_t kKiB = 1024;
constexpr std::uint64_t kMiB = kKiB * kKiB;
constexpr std::uint64_t kGiB = kMiB * kKiB;

TEST(MemorySize, ParsesBinaryAndDecimalUnitsAndPlainBytes) {
  EXPECT_EQ(parse_memory_size("512M"), 512 * kMiB);
  EXPECT_EQ(parse_memory_size("8G"), 8 * kGiB);
  EXPECT_EQ(parse_memory_size("8g"), 8 * kGiB);
  EXPECT_EQ(parse_memory_size("2GiB"), 2 * kGiB);
  EXPECT_EQ(parse_memory_size("2 gib"), 2 * kGiB);
  EXPECT_EQ(parse_memory_size("1.5G"), 3 * kGiB / 2);
  EXPECT_EQ(parse_memory_size("8GB"), 8'000'000'000u);
  EXPECT_EQ(parse_memory_size("64KB"), 64'000u);
  EXPECT_EQ(parse_memory_size("64K"), 64 * kKiB);
  EXPECT_EQ(parse_memory_size("1T"), 1024 * kGiB);
  EXPECT_EQ(parse_memory_size("1073741824"), kGiB);
  EXPECT_EQ(parse_memory_size("4096B"), 4096u);
  EXPECT_EQ(parse_memory_size(" 100 bytes "), 100u);
}

TEST(MemorySize, RefusesWhatIsNotASize) {
  for (const char* text : {"", "G", "abc", "12X", "-5G", "0", "0.0M", "1..5G", "1e9", "8 G B", "nan", "9E"}) {
    EXPECT_FALSE(parse_memory_size(text).has_value()) << "\"" << text << "\"";
  }
  EXPECT_FALSE(parse_memory_size("9000000T").has_value());  // 2^63 bytes and more
}

TEST(MemorySize, FormatsWithThreeSignificantFigures) {
  EXPECT_EQ(format_memory_size(12), "12 bytes");
  EXPECT_EQ(format_memory_size(1), "1 byte");
  EXPECT_EQ(format_memory_size(kKiB), "1.00 KiB");
  EXPECT_EQ(format_memory_size(512 * kMiB), "512 MiB");
  EXPECT_EQ(format_memory_size(31 * kGiB + kGiB / 5), "31.2 GiB");
  EXPECT_EQ(format_memory_size(999 * kMiB), "999 MiB");
  EXPECT_EQ(format_memory_size(1023 * kMiB), "1.00 GiB");  // not "1023 MiB": 3 figures
}

}  // namespace
}  // namespace clothsim
