// SIMD vectors for the engine's own product kernels (internal to libshared/nn): GCC/Clang vector
// extensions, so the compiler picks the instructions for the build's -march (AVX-512 where the
// machine has it, SSE2 at the least).
#pragma once

#include <Eigen/Core>
#include <cstring>

namespace df::nn::detail {

#if defined(__AVX512F__)
constexpr int kVectorBytes = 64;
#elif defined(__AVX__)
constexpr int kVectorBytes = 32;
#else
constexpr int kVectorBytes = 16;
#endif

template <class T>
struct Vector;
template <>
struct Vector<float> {
  typedef float type __attribute__((vector_size(kVectorBytes)));
};
template <>
struct Vector<double> {
  typedef double type __attribute__((vector_size(kVectorBytes)));
};

/// One vector from (possibly unaligned) memory.
template <class T>
typename Vector<T>::type load(const T* p) {
  typename Vector<T>::type v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

template <class T>
constexpr Eigen::Index kLanes = kVectorBytes / static_cast<Eigen::Index>(sizeof(T));

/// The instruction set the engine's kernels were built for, in words (the benchmarks print it).
constexpr const char* kVectorIsa =
#if defined(__AVX512F__)
    "AVX-512, 16 float lanes";
#elif defined(__AVX2__) && defined(__FMA__)
    "AVX2 + FMA, 8 float lanes";
#elif defined(__AVX__)
    "AVX, 8 float lanes";
#else
    "SSE2, 4 float lanes";
#endif

}  // namespace df::nn::detail
