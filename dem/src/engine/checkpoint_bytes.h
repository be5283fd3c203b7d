#ifndef BOUNCECAL_DEM_ENGINE_CHECKPOINT_BYTES_H_
#define BOUNCECAL_DEM_ENGINE_CHECKPOINT_BYTES_H_

// The byte layer of a pack checkpoint (packing_checkpoint.cc): values and arrays of trivially
// copyable values appended to a string in the host's own representation, and read back with
// every length checked against what is left. A checkpoint is resumed on the machine (or one of
// the same architecture) that wrote it; bit-identical resumption needs the doubles' exact bits,
// which text would not keep without care, and the header's byte-order mark refuses the others.

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "bouncecal/error.h"

namespace bouncecal::dem::scene {

// FNV-1a, 64 bit: the checkpoint's payload checksum and the set-up fingerprint. Not a defence
// against tampering, only against truncation, bit rot and mixing up files.
inline std::uint64_t Fnv1a(std::string_view bytes, std::uint64_t hash = 14695981039346656037ull) {
  for (const char c : bytes) hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return hash;
}

class ByteWriter {
 public:
  template <class T>
  void Put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <class T>
  void PutVector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    Put(static_cast<std::uint64_t>(values.size()));
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void PutString(std::string_view text) {
    Put(static_cast<std::uint64_t>(text.size()));
    bytes_.append(text);
  }
  const std::string& bytes() const { return bytes_; }
  std::string& mutable_bytes() { return bytes_; }

 private:
  std::string bytes_;
};

// Throws InputError "<name>: <problem>" on any read past the end, so a truncated or garbled
// payload can never be read as state.
class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

  template <class T>
  T Get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    Take(&value, sizeof(T));
    return value;
  }
  template <class T>
  std::vector<T> GetVector() {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto count = Get<std::uint64_t>();
    if (count > left() / (sizeof(T) > 0 ? sizeof(T) : 1)) Fail("it ends early (truncated)");
    std::vector<T> values(static_cast<std::size_t>(count));
    Take(values.data(), values.size() * sizeof(T));
    return values;
  }
  std::string GetString() {
    const auto count = Get<std::uint64_t>();
    if (count > left()) Fail("it ends early (truncated)");
    std::string text(bytes_.substr(at_, static_cast<std::size_t>(count)));
    at_ += static_cast<std::size_t>(count);
    return text;
  }
  std::size_t left() const { return bytes_.size() - at_; }
  [[noreturn]] void Fail(std::string_view problem) const {
    throw InputError(name_ + ": " + std::string(problem) +
                     "; the checkpoint is damaged, use an earlier one or start again");
  }

 private:
  void Take(void* out, std::size_t size) {
    if (size > left()) Fail("it ends early (truncated)");
    if (size > 0) std::memcpy(out, bytes_.data() + at_, size);
    at_ += size;
  }

  std::string_view bytes_;
  std::string name_;
  std::size_t at_ = 0;
};

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_CHECKPOINT_BYTES_H_
