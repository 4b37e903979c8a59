#include "geobrush/hash.hpp"

#include <cstdio>

namespace geobrush {
namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace

std::string toHex(Hash hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

void Hasher::mixWord(std::uint64_t word) {
  // Rotating the state before each word makes the digest order-sensitive.
  state_ = splitmix64(((state_ << 23) | (state_ >> 41)) ^ word);
  ++count_;
}

Hasher& Hasher::bytes(const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    std::uint64_t word;
    std::memcpy(&word, p + i, 8);
    mixWord(word);
  }
  if (i < size) {
    std::uint64_t tail = 0;
    std::memcpy(&tail, p + i, size - i);
    mixWord(tail ^ (std::uint64_t(size - i) << 56));
  }
  return *this;
}

Hash Hasher::digest() const {
  return splitmix64(state_ ^ count_);
}

}  // namespace geobrush
