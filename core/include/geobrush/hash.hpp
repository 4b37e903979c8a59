// Deterministic 64-bit hashing for cache keys and value content hashes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

namespace geobrush {

using Hash = std::uint64_t;

// Hex form of a hash, as printed in reports.
std::string toHex(Hash hash);

// Streams bytes into a 64-bit digest. Word-at-a-time with a SplitMix64
// finalizer per word: fast on large meshes and stable across runs and
// machines of the same endianness (the cache never leaves the process).
class Hasher {
 public:
  explicit Hasher(std::uint64_t seed = 0x9e3779b97f4a7c15ull) : state_(seed) {}

  Hasher& bytes(const void* data, std::size_t size);
  Hasher& str(std::string_view text) {
    u64(text.size());
    return bytes(text.data(), text.size());
  }
  Hasher& u64(std::uint64_t value) {
    mixWord(value);
    return *this;
  }
  Hasher& f64(double value) {
    // +0.0 and -0.0 compare equal, so they hash equal.
    if (value == 0.0) value = 0.0;
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return u64(bits);
  }
  template <typename T>
  requires std::is_trivially_copyable_v<T> Hasher& span(std::span<const T> values) {
    u64(values.size());
    return bytes(values.data(), values.size_bytes());
  }

  Hash digest() const;

 private:
  void mixWord(std::uint64_t word);
  std::uint64_t state_;
  std::uint64_t count_ = 0;
};

}  // namespace geobrush
