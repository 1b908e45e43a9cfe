// StateArchive: one list of fields that both saves and restores a piece of state.
//
// A component that can be checkpointed writes one function, `transfer(StateArchive&)`, that names
// each of its fields once, in a fixed order. Given a saving archive the function reads the fields
// and the archive writes them out; given a loading archive the archive overwrites the same fields
// with the stored values. So what is saved and what is restored cannot drift apart: there is one
// list (after the serialize() functions of Boost.Serialization and of cereal).
//
// Fields are named, and a loading archive checks every name and length against what it reads, so a
// file from another build or another scene fails with a message naming the field instead of
// loading garbage. Arrays whose length the model fixes (one value per particle) are transferred
// through spans: loading checks the stored length. Lists of any length (the anchors) go through
// vector(), which stores the length first and resizes on loading.
//
// The file format around the fields is io/checkpoint.h's; this interface knows nothing of files.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/vec3.h"

namespace clothsim {

class StateArchive {
 public:
  virtual ~StateArchive() = default;
  // True when the archive overwrites the fields (restoring), false when it reads them (saving).
  virtual bool loading() const = 0;

  // Scalars.
  virtual void value(std::string_view name, double& x) = 0;
  virtual void value(std::string_view name, std::uint64_t& x) = 0;
  virtual void text(std::string_view name, std::string& x) = 0;
  // Arrays of a length fixed by the caller: loading throws unless the stored length equals x.size().
  virtual void array(std::string_view name, std::span<double> x) = 0;
  virtual void array(std::string_view name, std::span<Vec3> x) = 0;
  virtual void array(std::string_view name, std::span<std::uint8_t> x) = 0;
  virtual void array(std::string_view name, std::span<std::uint32_t> x) = 0;
  virtual void array(std::string_view name, std::span<std::int32_t> x) = 0;
  // Loading: throws unless `count` more values of `size` bytes can follow (so a corrupted length
  // fails before it allocates). Saving: nothing.
  virtual void expect_values(std::uint64_t count, std::size_t size) = 0;

  // Any integer, enum or bool, stored as 64 bits.
  template <typename T>
  requires(std::is_integral_v<T> || std::is_enum_v<T>) void value(std::string_view name, T& x) {
    std::uint64_t stored = static_cast<std::uint64_t>(x);
    value(name, stored);
    if (loading()) x = static_cast<T>(stored);
  }
  void value(std::string_view name, Vec3& x) { array(name, std::span<Vec3>(&x, 1)); }

  // A vector of any length: its length (as "<name>.size"), then its values.
  template <typename T>
  void vector(std::string_view name, std::vector<T>& x) {
    std::uint64_t size = x.size();
    value(std::string(name) + ".size", size);
    if (loading()) {
      expect_values(size, sizeof(T));
      x.resize(static_cast<std::size_t>(size));
    }
    array(name, std::span<T>(x));
  }
};

}  // namespace clothsim
