// CRC-32 (the IEEE 802.3 polynomial, reflected, as in zlib, PNG and gzip): the checksum of
// checkpoint files (io/checkpoint.h). It detects every burst error of up to 32 bits and, for the
// truncations and overwritten blocks a crash or a bad disk leaves, all but one in 2^32.
#pragma once

#include <cstddef>
#include <cstdint>

namespace clothsim {

// The CRC of `bytes` bytes at `data`, continuing from `crc` (0 to start): crc32(b, crc32(a)) is
// the CRC of a followed by b. crc32("123456789") == 0xCBF43926.
std::uint32_t crc32(const void* data, std::size_t bytes, std::uint32_t crc = 0);

}  // namespace clothsim
