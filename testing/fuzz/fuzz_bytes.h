// Fuzz input as a stream of typed values: each read takes the next sizeof(T) bytes, or gives T{} (zero) once
// the input is exhausted, so every byte string is a valid input and a corpus file means the same thing to
// every target that reads it this way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "util/math.h"

namespace whitted_fuzz {

struct Bytes {
  const uint8_t* p;
  size_t n;

  Bytes(const uint8_t* data, size_t size) : p(data), n(size) {}

  template <typename T>
  T get() {
    T v{};
    if (n >= sizeof v) {
      std::memcpy(&v, p, sizeof v);
      p += sizeof v;
      n -= sizeof v;
    }
    return v;
  }
  uint8_t u8() { return get<uint8_t>(); }
  bool bit() { return u8() & 1; }
  double d() { return get<double>(); }
  float f() { return get<float>(); }
  whitted::Vec3 v3() {  // named locals: the three reads happen in this order
    double a = d(), b = d(), c = d();
    return whitted::Vec3(a, b, c);
  }
  whitted::Color col() {
    float a = f(), b = f(), c = f();
    return whitted::Color(a, b, c);
  }
};

}  // namespace whitted_fuzz
