// Host shim: compiles the `.cu` kernels of `kernels/` as plain C++ so they run on the CPU, one
// thread index after another, over the whole launch grid (`SPH_LAUNCH`). The kernels follow the
// rules of `sph.cuh` (no shared memory, no barriers, no warp intrinsics), so running the threads
// in sequence is one of the orders the GPU may run them in, and the atomics below are exact.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstring>
#include <algorithm>

#define __global__
#define __device__
#define __host__
// `static`: the shim is built once per dimension and both libraries are linked into one binary;
// an `inline` helper (`vload`, `smoothing`, a kernel's template body) has the same mangled name
// in both but a different body (the vector length D), and the linker would keep one of them for
// both dimensions. Every device helper is `__device__ __forceinline__`, so each library keeps its
// own.
#define __forceinline__ static inline
#define __restrict__

using std::floor;
using std::pow;
using std::sqrt;
using std::fabs;
inline float floorf(float x) { return std::floor(x); }
inline float sqrtf(float x) { return std::sqrt(x); }
inline float fabsf(float x) { return std::fabs(x); }
inline float fmaxf(float a, float b) { return std::fmax(a, b); }
inline float fminf(float a, float b) { return std::fmin(a, b); }

struct sph_uint3 {
    unsigned int x, y, z;
};

// The launch indices of the thread being run (one at a time). Per OS thread: tests call the
// launchers from several threads at once.
static thread_local sph_uint3 threadIdx, blockIdx, blockDim, gridDim;

inline unsigned int atomicAdd(unsigned int* a, unsigned int v) { unsigned int o = *a; *a += v; return o; }
inline int atomicAdd(int* a, int v) { int o = *a; *a += v; return o; }
inline float atomicAdd(float* a, float v) { float o = *a; *a += v; return o; }
inline double atomicAdd(double* a, double v) { double o = *a; *a += v; return o; }
inline unsigned int atomicMax(unsigned int* a, unsigned int v) { unsigned int o = *a; *a = std::max(o, v); return o; }
inline int atomicMax(int* a, int v) { int o = *a; *a = std::max(o, v); return o; }
inline unsigned int atomicMin(unsigned int* a, unsigned int v) { unsigned int o = *a; *a = std::min(o, v); return o; }
inline int atomicMin(int* a, int v) { int o = *a; *a = std::min(o, v); return o; }
inline float __int_as_float(int i) { float f; std::memcpy(&f, &i, 4); return f; }
inline int __float_as_int(float f) { int i; std::memcpy(&i, &f, 4); return i; }

// Runs `kernel(args...)` for every thread of a 1D launch of `blocks` x `threads`.
#define SPH_LAUNCH(blocks, threads, kernel, ...)                              \
    do {                                                                      \
        gridDim = {(unsigned)(blocks), 1u, 1u};                               \
        blockDim = {(unsigned)(threads), 1u, 1u};                             \
        for (unsigned _b = 0; _b < (unsigned)(blocks); ++_b) {                \
            for (unsigned _t = 0; _t < (unsigned)(threads); ++_t) {           \
                blockIdx = {_b, 0u, 0u};                                      \
                threadIdx = {_t, 0u, 0u};                                     \
                kernel(__VA_ARGS__);                                          \
            }                                                                 \
        }                                                                     \
    } while (0)

// The launch shape the CUDA backend uses for n items (`backend::cuda::launch`): 256 threads.
#define SPH_THREADS 256u
#define SPH_BLOCKS(n) (((unsigned)(n) + SPH_THREADS - 1u) / SPH_THREADS)
