// FNV-1a, 64 bits: a fast, well-defined hash of bytes, for checksums and
// fingerprints (not for security). The same input gives the same value on
// every run and machine of the same byte order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace softflow {

class Fnv1a {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
      value_ ^= p[i];
      value_ *= 1099511628211ULL;  // the 64-bit FNV prime
    }
  }
  /// The bytes of one value (an arithmetic type, or an array of them).
  template <class T>
  void scalar(const T& x) {
    bytes(&x, sizeof x);
  }
  /// The length, then the characters: "ab" + "c" and "a" + "bc" differ.
  void text(const std::string& s) {
    scalar(s.size());
    bytes(s.data(), s.size());
  }
  /// The length, then the elements' bytes (T without padding).
  template <class T>
  void array(const std::vector<T>& values) {
    scalar(values.size());
    if (!values.empty()) bytes(values.data(), values.size() * sizeof(T));
  }
  [[nodiscard]] std::uint64_t value() const { return value_; }

 private:
  std::uint64_t value_ = 14695981039346656037ULL;  // the 64-bit FNV offset basis
};

}  // namespace softflow
