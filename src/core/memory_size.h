// Sizes of memory as people write them: "512M", "8G", "2GiB", "1.5GB", "1073741824".
//
// K, M, G, T and KiB, MiB, GiB, TiB are powers of 1024 (what `free -h`, ulimit and Docker mean by
// "8G"); KB, MB, GB, TB are powers of 1000 (what disk vendors mean): "8G" and "8GiB" are 8 x 2^30
// bytes, "8GB" is 8 x 10^9. A plain number (or one followed by B or bytes) is bytes. Letters may
// be lower or upper case, a space may separate the unit, and the number may have a fraction
// ("1.5G"). Printed sizes are binary with 3 significant figures: "31.2 GiB", "512 MiB".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace clothsim {

// The accepted forms, for messages: "a size such as 512M, 8G, 2GiB, 1.5GB or a number of bytes ...".
std::string_view memory_size_forms();

// The size `text` names, in bytes, or nothing if it is not a size of the forms above, or is 0, or
// is 2^63 bytes or more.
std::optional<std::uint64_t> parse_memory_size(std::string_view text);

// "31.2 GiB", "512 MiB", "1.00 KiB", "12 bytes".
std::string format_memory_size(std::uint64_t bytes);

}  // namespace clothsim
