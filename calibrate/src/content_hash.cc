#include "bouncecal/calibrate/content_hash.h"

#include <array>
#include <cstdio>
#include <fstream>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {

void Fnv1a64::Update(std::span<const std::byte> data) {
  for (std::byte byte : data) {
    state_ ^= static_cast<std::uint64_t>(byte);
    state_ *= kPrime;
  }
}

void Fnv1a64::Update(std::string_view text) {
  Update(std::as_bytes(std::span<const char>(text.data(), text.size())));
}

std::string FileContentHash(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) {
    throw InputError("cannot read '" + path.string() +
                     "' to hash it; check that the file exists and is readable");
  }
  Fnv1a64 hash;
  std::array<char, 1 << 16> buffer{};
  while (stream) {
    stream.read(buffer.data(), buffer.size());
    hash.Update(std::string_view(buffer.data(), static_cast<size_t>(stream.gcount())));
  }
  if (stream.bad()) {
    throw InputError("reading '" + path.string() + "' failed while hashing it");
  }
  std::array<char, 17> hex{};
  std::snprintf(hex.data(), hex.size(), "%016llx", static_cast<unsigned long long>(hash.digest()));
  return "fnv1a64:" + std::string(hex.data());
}

}  // namespace bouncecal::calibrate
