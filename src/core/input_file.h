// Reading a file the user named (a scene, a viewer script): the whole text, or an InputError
// naming the path and the system's reason, so every input file fails the same way.
#pragma once

#include <string>

namespace clothsim {

// The whole content of `path`. Throws InputError(path, "", "cannot read file: <reason>") if it
// cannot be opened or read (a directory included).
std::string read_input_file(const std::string& path);

}  // namespace clothsim
