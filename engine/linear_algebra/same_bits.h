// Whether two arrays of doubles hold the same bits: what a memo compares its inputs with before it
// reuses a result. Equal values are not enough where a result's bits are asked for: −0 == +0, and a
// product with either may keep the sign.
#pragma once

#include <cstddef>
#include <cstring>

namespace csim {

inline bool same_bits(const double* a, const double* b, std::size_t count) {
  return count == 0 || std::memcmp(a, b, count * sizeof(double)) == 0;
}

}  // namespace csim
