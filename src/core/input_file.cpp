#include "core/input_file.h"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.h"

namespace clothsim {

std::string read_input_file(const std::string& path) {
  errno = 0;
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) throw InputError(path, "", std::string("cannot read file: ") + std::strerror(errno));
  std::string text;
  std::array<char, 65536> buffer{};
  std::size_t count = 0;
  while ((count = std::fread(buffer.data(), 1, buffer.size(), file)) > 0) text.append(buffer.data(), count);
  // Reading a directory opens fine on Linux and fails here with EISDIR.
  const bool read_failed = std::ferror(file) != 0;
  const int read_errno = errno;
  std::fclose(file);
  if (read_failed) throw InputError(path, "", std::string("cannot read file: ") + std::strerror(read_errno));
  return text;
}

}  // namespace clothsim
